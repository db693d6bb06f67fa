# Prints table.md from OUT (default /tmp/gt): run.sh's reports, "old" = the
# last-5 median, "half" = the view's triangles (change 1 alone), "defer" =
# with change 2 (deferred at the keyframe only), "final" = changes 1-3 (the
# program as committed).
import json, os, sys
out = sys.argv[1] if len(sys.argv) > 1 else "/tmp/gt"
names = ["indoor", "indoor_1M", "outdoor_100k", "q3_oa_dm5", "q3_aggressor", "q3_delta",
         "torcs_forza", "torcs_e-track-2", "morse_land-1_trees", "q3_ps37ctf"]
label = {"old": "last-5 median", "half": "1: view triangles", "defer": "1 + 2 at keyframes",
         "final": "1 + 2 + 3 (now)"}
fmt = lambda v: "–" if v is None else f"{v:.2f}"
print("| path | geometry cost | pass | frames g/w/k | frame/reference median, p95 | warped PSNR median / p5 |")
print("|---|---|---|---|---|---|")
for n in names:
    for b in ["old", "half", "defer", "final"]:
        for p in ["1", "2"]:
            f = f"{out}/{n}_{b}_{p}/report.json"
            if not os.path.exists(f):
                continue
            s = json.load(open(f))["summary"]
            m, fo, ps = s["frames_by_mode"], s["frame_over_reference"], s.get("psnr") or {}
            print(f"| {n} | {label[b]} | {p} | {m['geometry']}/{m['warp']}/{m['keyframe']} | "
                  f"{fo['median']:.2f}, {fo['p95']:.2f} | {fmt(ps.get('median'))} / {fmt(ps.get('p5'))} |")
