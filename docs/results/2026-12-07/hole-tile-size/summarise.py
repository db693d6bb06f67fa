#!/usr/bin/env python3
"""results.csv and tiles.png from run.sh's walks: per scene and tile size,
the in-between frames' PSNR (mean, p5), ms.frame, hole pass ms, rectangle
pixels and triangles submitted (medians), and frame / geometry (median)."""
import csv, glob, json, os, statistics as st, sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

out = sys.argv[1]
here = os.path.dirname(os.path.abspath(__file__))
rows = {}
for d in sorted(glob.glob(os.path.join(out, "*-*"))):
    name, tile = os.path.basename(d).rsplit("-", 1)
    r = json.load(open(os.path.join(d, "report.json")))
    w = [f for f in r["frames"] if f["mode"] == "warp"]
    ps = sorted(f["psnr"] for f in w if f["psnr"] is not None)
    rows[(name, int(tile))] = {
        "psnr_mean": st.mean(ps), "psnr_p5": ps[len(ps) // 20],
        "frame_ms_median": st.median(f["ms"]["frame"] for f in w),
        "hole_ms_median": st.median(f["ms"]["render_holes"] for f in w),
        "hole_rect_pixels_median": float(st.median(f["hole_rect_pixels"] for f in w)),
        "holes_rendered_median": float(st.median(f["holes_rendered"] for f in w)),
        "hole_triangles_median": float(st.median(f["hole_triangles"] for f in w)),
        "frame_over_geometry_median": r["summary"]["frame_over_reference"]["median"],
    }
cols = list(next(iter(rows.values())).keys())
names = sorted({k[0] for k in rows})
tiles = sorted({k[1] for k in rows})
with open(os.path.join(here, "results.csv"), "w", newline="") as f:
    wr = csv.writer(f)
    wr.writerow(["scene", "hole_tile_px"] + cols)
    for n in names:
        for t in tiles:
            wr.writerow([n, t] + ["%.3f" % rows[(n, t)][c] for c in cols])
for n in names:
    print("%-30s" % n + "  ".join("t%d: psnr %.2f p5 %.2f holes %.2f ms frame %.2f rectpx %d tri %d" % (
        t, rows[(n, t)]["psnr_mean"], rows[(n, t)]["psnr_p5"], rows[(n, t)]["hole_ms_median"],
        rows[(n, t)]["frame_ms_median"], rows[(n, t)]["hole_rect_pixels_median"],
        rows[(n, t)]["hole_triangles_median"]) for t in tiles))

fig, axes = plt.subplots(1, 2, figsize=(11, 4))
short = [n.replace("morse_tum_kitchen_", "").replace("q3_", "").replace("torcs_", "") for n in names]
xs = list(range(len(names)))
colours = {8: "#55a868", 16: "#4c72b0", 32: "#dd8452"}
for ax, key, title in ((axes[0], "psnr_mean", "in-between PSNR, mean (dB)"),
                       (axes[1], "hole_ms_median", "hole pass ms, median")):
    for k, t in enumerate(tiles):
        ax.bar([x + (k - 1) * 0.27 for x in xs], [rows[(n, t)][key] for n in names], 0.27,
               color=colours.get(t, None), label="--hole-tile-px %d%s" % (t, " (default)" if t == 16 else ""))
    ax.set_title(title, fontsize=9)
    ax.set_xticks(xs)
    ax.set_xticklabels(short, fontsize=7, rotation=20)
    ax.legend(fontsize=7)
    if key == "psnr_mean":
        ax.set_ylim(min(v[key] for v in rows.values()) - 2, None)
fig.suptitle("Hole tile size, walk --mode hybrid at 512x512, llvmpipe 2 threads, 2-vCPU VM", fontsize=9)
fig.tight_layout()
fig.savefig(os.path.join(here, "tiles.png"), dpi=110)
