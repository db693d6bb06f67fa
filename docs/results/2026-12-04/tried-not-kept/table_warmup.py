# Prints table.md from run.sh's reports (default /tmp/wg): "old" = the warm-up
# geometry sample is the second render, "new" = the faster of the second and third.
import json, os, sys
out = sys.argv[1] if len(sys.argv) > 1 else "/tmp/wg"
names = ["indoor", "indoor_1M", "outdoor_100k", "q3_oa_dm5", "q3_aggressor", "q3_delta",
         "torcs_forza", "torcs_e-track-2", "morse_land-1_trees", "q3_ps37ctf"]
label = {"old": "2nd render", "new": "faster of 2nd, 3rd"}
fmt = lambda v: "–" if v is None else f"{v:.2f}"
print("| path | warm-up sample | pass | frames g/w/k | frame/reference median, p95 | warped PSNR median / p5 |")
print("|---|---|---|---|---|---|")
for n in names:
    for b in ["old", "new"]:
        for p in ["1", "2"]:
            f = f"{out}/{n}_{b}_{p}/report.json"
            if not os.path.exists(f):
                continue
            s = json.load(open(f))["summary"]
            m, fo, ps = s["frames_by_mode"], s["frame_over_reference"], s.get("psnr") or {}
            print(f"| {n} | {label[b]} | {p} | {m['geometry']}/{m['warp']}/{m['keyframe']} | "
                  f"{fo['median']:.2f}, {fo['p95']:.2f} | {fmt(ps.get('median'))} / {fmt(ps.get('p5'))} |")
