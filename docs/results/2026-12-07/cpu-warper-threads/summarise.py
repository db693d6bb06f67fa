#!/usr/bin/env python3
"""Summarises run.sh's walks: per scene, mode and variant (old, t1, t2) and
round, the warped frames, the medians over warped frames of ms.frame, the
layers (ms.warp_a + ms.warp_b) and the hole pass (ms.render_holes), the mean
PSNR of warped frames, summary.frame_over_reference, and the share of frames
two rounds drew the same way (geometry vs warped). Writes results.csv,
results.json and layers.png next to this script.

Usage: /usr/bin/python3 summarise.py OUT   (OUT as given to run.sh)
"""
import csv
import glob
import json
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
VARIANTS = ["old", "t1", "t2"]
NAME = {"indoor_1M": "indoor:1M", "q3_oa_dm5": "q3:oa_dm5", "q3_ps37ctf": "q3:ps37ctf",
        "morse_tum_kitchen_tum_kitchen": "morse:tum_kitchen", "torcs_forza": "torcs:forza"}
LABEL = {"old": "before (1 thread)", "t1": "now, 1 thread", "t2": "now, 2 threads"}


def load(out):
    runs = {}
    for d in sorted(glob.glob(os.path.join(out, "*-r*"))):
        rep = os.path.join(d, "report.json")
        if not os.path.exists(rep):
            continue
        name, rnd = os.path.basename(d).rsplit("-r", 1)
        scene, mode, variant = name.rsplit("-", 2)
        r = json.load(open(rep))
        s, frames = r["summary"], r["frames"]
        warp = [f for f in frames if f.get("mode") == "warp"]
        med = lambda k: statistics.median([f["ms"].get(k, 0.0) for f in warp]) if warp else None
        psnrs = [f["psnr"] for f in warp if f.get("psnr") is not None]
        fo = s.get("frame_over_reference") or {}
        runs[(scene, mode, variant, int(rnd))] = {
            "scene": scene, "mode": mode, "variant": variant, "round": int(rnd),
            "warped_frames": len(warp),
            "in_between_ms": med("frame"),
            "layers_ms": (med("warp_a") + med("warp_b")) if warp else None,
            "hole_pass_ms": med("render_holes"),
            "psnr_mean": statistics.mean(psnrs) if psnrs else None,
            "frame_over_geometry_median": fo.get("median"),
            "frame_over_geometry_p95": fo.get("p95"),
            "warper_threads": s.get("warper_threads"),
            "modes": [f.get("mode") != "geometry" for f in frames],
        }
    return runs


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    runs = load(sys.argv[1])
    rows = []
    for key in sorted(runs):
        v = dict(runs[key])
        other = runs.get((key[0], key[1], key[2], 3 - key[3]))
        v["same_mode_share"] = (sum(a == b for a, b in zip(v["modes"], other["modes"])) /
                                len(v["modes"])) if other else None
        del v["modes"]
        rows.append(v)
    fields = list(rows[0].keys())
    with open(os.path.join(HERE, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        for r in rows:
            w.writerow({k: (round(x, 4) if isinstance(x, float) else x) for k, x in r.items()})
    json.dump(rows, open(os.path.join(HERE, "results.json"), "w"), indent=1)
    # Per scene and mode: the median over rounds.
    table = {}
    for r in rows:
        table.setdefault((r["scene"], r["mode"], r["variant"]), []).append(r)
    def m(key, field):
        vals = [r[field] for r in table.get(key, []) if r[field] is not None]
        return statistics.median(vals) if vals else None
    scenes = sorted({r["scene"] for r in rows}, key=lambda s: [x["scene"] for x in rows].index(s))
    for mode in ("hybrid", "auto"):
        print("\n--mode %s" % mode)
        for sc in scenes:
            cells = []
            for v in VARIANTS:
                k = (sc, mode, v)
                if k not in table:
                    continue
                fmt = lambda x, d=2: "-" if x is None else ("%.*f" % (d, x))
                cells.append("%s: warped %s, frame %s, layers %s, holes %s, f/g %s / %s, PSNR %s, same %s" % (
                    v, "/".join(str(r["warped_frames"]) for r in table[k]), fmt(m(k, "in_between_ms")),
                    fmt(m(k, "layers_ms")), fmt(m(k, "hole_pass_ms")),
                    fmt(m(k, "frame_over_geometry_median")), fmt(m(k, "frame_over_geometry_p95")),
                    fmt(m(k, "psnr_mean")), fmt(m(k, "same_mode_share"))))
            print("%s | %s" % (sc, " | ".join(cells)))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    for ax, field, title in ((axes[0], "layers_ms", "both warped layers (ms.warp_a + warp_b)"),
                             (axes[1], "in_between_ms", "in-between frame (ms.frame)")):
        width = 0.27
        for i, v in enumerate(VARIANTS):
            ys = [m((sc, "hybrid", v), field) for sc in scenes]
            if all(y is None for y in ys):
                continue
            xs = [j + (i - 1) * width for j in range(len(scenes))]
            ax.bar(xs, [y or 0 for y in ys], width, label=LABEL[v])
        ax.set_xticks(range(len(scenes)))
        ax.set_xticklabels([NAME.get(s, s) for s in scenes], rotation=30, ha="right", fontsize=8)
        ax.set_ylabel("ms (median over warped frames and rounds)", fontsize=9)
        ax.set_title(title, fontsize=10)
        ax.legend(fontsize=8)
    fig.suptitle("CPU warper before and after, --mode hybrid, 512x512, Mesa llvmpipe, 2 vCPUs", fontsize=11)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "layers.png"), dpi=110)


if __name__ == "__main__":
    main()
