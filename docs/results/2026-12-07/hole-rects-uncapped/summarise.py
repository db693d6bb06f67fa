#!/usr/bin/env python3
"""results.csv and rects.png from run.sh's walks: per scene, mode and
setting, the in-between frames warped, their PSNR (mean, p5), ms.frame and
hole pass ms (medians), the rectangles drawn (median, max), and the walk's
frame / geometry ratio (median, p95)."""
import csv, glob, json, os, statistics as st, sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

out = sys.argv[1]
here = os.path.dirname(os.path.abspath(__file__))
rows = {}
for d in sorted(glob.glob(os.path.join(out, "*-*-*"))):
    name, mode, variant = os.path.basename(d).rsplit("-", 2)
    r = json.load(open(os.path.join(d, "report.json")))
    w = [f for f in r["frames"] if f["mode"] == "warp"]
    ps = sorted(f["psnr"] for f in w if f["psnr"] is not None)
    rects = [f["hole_rects"] for f in w]
    fg = r["summary"]["frame_over_reference"]
    rows[(name, mode, variant)] = {
        "warped_frames": len(w),
        "psnr_mean": st.mean(ps) if ps else float("nan"),
        "psnr_p5": ps[len(ps) // 20] if ps else float("nan"),
        "frame_ms_median": st.median(f["ms"]["frame"] for f in w) if w else float("nan"),
        "hole_ms_median": st.median(f["ms"]["render_holes"] for f in w) if w else float("nan"),
        "hole_rects_median": float(st.median(rects)) if rects else float("nan"),
        "hole_rects_max": max(rects) if rects else 0,
        "frame_over_geometry_median": fg["median"],
        "frame_over_geometry_p95": fg["p95"],
    }
cols = ["warped_frames", "psnr_mean", "psnr_p5", "frame_ms_median", "hole_ms_median",
        "hole_rects_median", "hole_rects_max", "frame_over_geometry_median",
        "frame_over_geometry_p95"]
names = sorted({k[0] for k in rows})
with open(os.path.join(here, "results.csv"), "w", newline="") as f:
    wr = csv.writer(f)
    wr.writerow(["scene", "mode", "hole_rects_max"] + cols)
    for n in names:
        for m in ("hybrid", "auto"):
            for v in ("capped", "uncapped"):
                x = rows[(n, m, v)]
                wr.writerow([n, m, 12 if v == "capped" else 0] +
                            [("%.3f" % x[c]) if isinstance(x[c], float) else x[c] for c in cols])
for m in ("hybrid", "auto"):
    print("--mode", m)
    for n in names:
        a, b = rows[(n, m, "capped")], rows[(n, m, "uncapped")]
        print("  %-30s warped %3d/%3d  psnr %.2f/%.2f (p5 %.2f/%.2f)  frame %.2f/%.2f ms  holes %.2f/%.2f ms"
              "  rects max %d/%d  f/g median %.3f/%.3f p95 %.3f/%.3f" % (
                  n, a["warped_frames"], b["warped_frames"], a["psnr_mean"], b["psnr_mean"],
                  a["psnr_p5"], b["psnr_p5"], a["frame_ms_median"], b["frame_ms_median"],
                  a["hole_ms_median"], b["hole_ms_median"], a["hole_rects_max"], b["hole_rects_max"],
                  a["frame_over_geometry_median"], b["frame_over_geometry_median"],
                  a["frame_over_geometry_p95"], b["frame_over_geometry_p95"]))

fig, axes = plt.subplots(1, 3, figsize=(13, 4))
short = [n.replace("morse_tum_kitchen_", "").replace("q3_", "").replace("torcs_", "") for n in names]
xs = list(range(len(names)))
panels = [("hybrid", "psnr_mean", "--mode hybrid: in-between PSNR, mean (dB)"),
          ("hybrid", "hole_ms_median", "--mode hybrid: hole pass ms, median"),
          ("auto", "frame_over_geometry_median", "--mode auto: frame / geometry, median")]
for ax, (m, key, title) in zip(axes, panels):
    for v, off, c in (("capped", -0.2, "#4c72b0"), ("uncapped", 0.2, "#dd8452")):
        ax.bar([x + off for x in xs], [rows[(n, m, v)][key] for n in names], 0.4, color=c,
               label="--hole-rects-max 12 (default)" if v == "capped" else "--hole-rects-max 0 (every one)")
    ax.set_title(title, fontsize=9)
    ax.set_xticks(xs)
    ax.set_xticklabels(short, fontsize=7, rotation=20)
    ax.legend(fontsize=7)
    if key == "psnr_mean":
        ax.set_ylim(min(rows[(n, m, v)][key] for n in names for v in ("capped", "uncapped")) - 2, None)
fig.suptitle("Hole rectangles capped at 12 or not, walk at 512x512, llvmpipe 2 threads, 2-vCPU VM", fontsize=9)
fig.tight_layout()
fig.savefig(os.path.join(here, "rects.png"), dpi=110)
