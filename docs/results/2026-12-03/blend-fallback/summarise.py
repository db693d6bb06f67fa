#!/usr/bin/env python3
"""runs.csv, table.md and psnr_vs_ms.png from the walks run.sh wrote.
Usage: /usr/bin/python3 summarise.py OUTROOT   (the plot needs python3-matplotlib)"""
import csv, json, os, sys

root = sys.argv[1]
here = os.path.dirname(os.path.abspath(__file__))
SCENES = ["indoor", "sharp_turn", "oa_dm5", "forza"]
LODS = ["paper", "rl"]
MODES = ["overlay", "depth-merge", "blend"]
FALLBACKS = ["copy", "reproject"]

rows = []
for l in LODS:
    for s in SCENES:
        for c in MODES:
            for f in FALLBACKS:
                p = os.path.join(root, s, l, f"{c}-{f}", "report.json")
                if not os.path.exists(p):
                    continue
                sm = json.load(open(p))["summary"]
                g = lambda k, q="median": sm[k][q] if sm.get(k) and sm[k].get(q) is not None else float("nan")
                rows.append(dict(scene=s, lod=l, compose=c, fallback=f, layers=sm["layers"],
                                 psnr_median=g("psnr"), psnr_p5=g("psnr", "p5"),
                                 ssim_median=g("ssim"), in_between_ms=g("in_between_ms"),
                                 reference_ms=g("reference_ms"), compose_ms=g("compose_ms"),
                                 holes_before=g("holes_before_fallback"),
                                 stale_pixels=g("stale_pixels"), stale_pixels_p95=g("stale_pixels", "p95"),
                                 reprojected_pixels=g("reprojected_pixels"),
                                 blended_pixels=g("blended_pixels"),
                                 frames=sm["in_between_frames"]))
with open(os.path.join(here, "runs.csv"), "w", newline="") as fh:
    w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
    w.writeheader()
    w.writerows(rows)

def fmt(v, d=2):
    return "—" if v != v else f"{v:.{d}f}"

lines = ["| scene | LOD | compose | fallback | PSNR median | PSNR p5 | in-between ms | ms / overlay-copy | stale px median | blended px median |",
         "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
for r in rows:
    base = [b for b in rows if b["scene"] == r["scene"] and b["lod"] == r["lod"]
            and b["compose"] == "overlay" and b["fallback"] == "copy"]
    ratio = r["in_between_ms"] / base[0]["in_between_ms"] if base else float("nan")
    lines.append(f"| {r['scene']} | {r['lod']} | {r['compose']} | {r['fallback']} | {fmt(r['psnr_median'])} | "
                 f"{fmt(r['psnr_p5'])} | {fmt(r['in_between_ms'])} | {fmt(ratio)} | {fmt(r['stale_pixels'], 0)} | "
                 f"{fmt(r['blended_pixels'], 0)} |")
open(os.path.join(here, "table.md"), "w").write("\n".join(lines) + "\n")
print("\n".join(lines))

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
fig, axes = plt.subplots(2, len(SCENES), figsize=(4.2 * len(SCENES), 7.5), squeeze=False)
marker = {"overlay": "o", "depth-merge": "s", "blend": "^"}
colour = {"copy": "tab:blue", "reproject": "tab:red"}
for li, l in enumerate(LODS):
    for si, s in enumerate(SCENES):
        ax = axes[li][si]
        for r in rows:
            if r["scene"] != s or r["lod"] != l:
                continue
            ax.scatter(r["in_between_ms"], r["psnr_median"], marker=marker[r["compose"]],
                       color=colour[r["fallback"]], s=50)
            ax.scatter(r["in_between_ms"], r["psnr_p5"], marker=marker[r["compose"]],
                       facecolors="none", edgecolors=colour[r["fallback"]], s=50)
        ax.set_title(f"{s} / LOD {l}", fontsize=9)
        ax.set_xlabel("in-between ms (median)")
        ax.set_ylabel("PSNR dB (filled: median, open: p5)")
        ax.grid(alpha=0.3)
from matplotlib.lines import Line2D
handles = [Line2D([], [], marker=marker[c], linestyle="", color="grey", label=c) for c in MODES] + \
          [Line2D([], [], marker="o", linestyle="", color=colour[f], label=f"fallback {f}") for f in FALLBACKS]
fig.legend(handles=handles, loc="upper center", ncol=5)
fig.tight_layout(rect=(0, 0, 1, 0.95))
fig.savefig(os.path.join(here, "psnr_vs_ms.png"), dpi=90)
