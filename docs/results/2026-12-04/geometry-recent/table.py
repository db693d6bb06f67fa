import json,sys,os
names=["indoor","indoor_1M","outdoor_100k","q3_oa_dm5","q3_aggressor","q3_delta","torcs_forza","torcs_e-track-2","morse_land-1_trees"]
print("| path | chooser | pass | frames g/w/k | frame/reference median, p95 | warped PSNR median / p5 |")
print("|---|---|---|---|---|---|")
for n in names:
  for b in ["old","new"]:
    for p in ["1","2"]:
      f=f"/tmp/gr/{n}_{b}_{p}/report.json"
      if not os.path.exists(f): continue
      s=json.load(open(f))["summary"]; m=s["frames_by_mode"]; fo=s["frame_over_reference"]
      ps=s.get("psnr") or {}
      pm=ps.get("median") if isinstance(ps,dict) else None; p5=ps.get("p5") if isinstance(ps,dict) else None
      fmt=lambda v: "–" if v is None else f"{v:.2f}"
      print(f"| {n} | {'median of 15' if b=='old' else 'median of last 5'} | {p} | {m['geometry']}/{m['warp']}/{m['keyframe']} | {fo['median']:.2f}, {fo['p95']:.2f} | {fmt(pm)} / {fmt(p5)} |")
