#!/usr/bin/env python3
"""The hole pass from the scene's own triangles against the simplified copy.

Walks each scene in --mode hybrid (every in-between frame warped and every
hole rectangle drawn, so the two settings draw the same frames) with
--no-simplify-holes and --simplify-holes, interleaved, and writes OUT/
study.csv, OUT/study.json and OUT/study.png: per scene the median hole-pass
triangles and time, the median in-between frame time, the in-between PSNR
(median, p5, mean) and the wall time of the whole run (the copy is made
when the scene loads). Timing wants an idle machine.

Usage: /usr/bin/python3 scripts/simplify_holes_study.py [--bin build/bin/hybridwalk]
           [--out DIR] [--rounds N] [--plot-only] [SCENE ...]
The plot needs matplotlib (Debian python3-matplotlib).
"""
import argparse
import csv
import json
import os
import platform
import statistics
import subprocess
import sys
import time

SCENES = [
    # scene, extra walk arguments
    ("indoor", []),
    ("indoor:1M", []),
    ("outdoor", []),
    ("q3:oa_dm5", ["--path", "paths/oa_dm5.json"]),
    ("q3:oa_rpg3dm2", []),
    ("torcs:forza", []),
    ("torcs:alpine-1", []),
    ("morse:apartment", []),
    ("morse:tum_kitchen/tum_kitchen", []),
]
VARIANTS = [("own", "--no-simplify-holes"), ("simplified", "--simplify-holes")]


def median(v):
    return statistics.median(v) if v else None


def p5(v):
    v = sorted(v)
    return v[int(0.05 * (len(v) - 1))] if v else None


def walk(binary, scene, extra, flag, out):
    cmd = [binary, "walk", "--scene", scene, "--mode", "hybrid", "--width", "512", "--height",
           "512", "--quiet", "--out", out, flag] + extra
    os.makedirs(os.path.dirname(out), exist_ok=True)
    t = time.monotonic()
    with open(out + ".log", "w") as log:
        rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT)
    wall = time.monotonic() - t
    if rc != 0:
        sys.exit("%s failed (exit %d); see %s.log" % (" ".join(cmd), rc, out))
    r = json.load(open(os.path.join(out, "report.json")))
    warp = [f for f in r["frames"] if f.get("mode") == "warp"]
    psnr = [f["psnr"] for f in warp if f.get("psnr") is not None]
    return {
        "wall_s": wall,
        "warped_frames": len(warp),
        "hole_triangles": median([f["hole_triangles"] for f in warp if "hole_triangles" in f]),
        "render_holes_ms": median([f["ms"]["render_holes"] for f in warp
                                   if f.get("ms", {}).get("render_holes") is not None]),
        "frame_ms": median([f["ms"]["frame"] for f in warp]),
        "psnr_median": median(psnr),
        "psnr_p5": p5(psnr),
        "psnr_mean": statistics.mean(psnr) if psnr else None,
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default="build/bin/hybridwalk")
    ap.add_argument("--out", default="simplify-holes-study")
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--plot-only", action="store_true", help="redraw OUT/study.png from OUT/study.json")
    ap.add_argument("scenes", nargs="*")
    a = ap.parse_args()
    if a.plot_only:
        study = json.load(open(os.path.join(a.out, "study.json")))
        plot(study["rows"], study["meta"], a.out)
        return
    scenes = [(s, e) for s, e in SCENES if not a.scenes or s in a.scenes]
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for scene, extra in scenes:
        runs = {name: [] for name, _ in VARIANTS}
        for rnd in range(a.rounds):
            for name, flag in VARIANTS:
                d = os.path.join(a.out, "runs", scene.replace(":", "_").replace("/", "_"),
                                 "%s-%d" % (name, rnd))
                runs[name].append(walk(a.bin, scene, extra, flag, d))
                print(scene, name, rnd, runs[name][-1], flush=True)
        for name, _ in VARIANTS:
            rs = runs[name]
            row = {"scene": scene, "variant": name}
            for k in rs[0]:
                vals = [r[k] for r in rs if r[k] is not None]
                row[k] = median(vals) if vals else None
            rows.append(row)
    keys = list(rows[0].keys())
    with open(os.path.join(a.out, "study.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    meta = {"machine": platform.processor() or platform.machine(), "cpus": os.cpu_count(),
            "lp_num_threads": os.environ.get("LP_NUM_THREADS"), "rounds": a.rounds,
            "settings": "walk --mode hybrid --width 512 --height 512, defaults otherwise"}
    json.dump({"meta": meta, "rows": rows}, open(os.path.join(a.out, "study.json"), "w"), indent=1)
    plot(rows, meta, a.out)


def plot(rows, meta, out):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("no matplotlib: study.png not written", file=sys.stderr)
        return
    names = list(dict.fromkeys(r["scene"] for r in rows))
    by = {(r["scene"], r["variant"]): r for r in rows}
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    x = range(len(names))
    for i, (name, _) in enumerate(VARIANTS):
        ax[0].bar([k + 0.4 * i - 0.2 for k in x],
                  [by[(s, name)]["render_holes_ms"] or 0 for s in names], 0.4,
                  label="hole rectangles from the %s triangles" % ("scene's own" if name == "own" else "simplified copy's"))
    ax[0].set_ylabel("hole pass, median (ms)")
    ax[0].set_xticks(list(x))
    ax[0].set_xticklabels(names, rotation=35, ha="right", fontsize=8)
    ax[0].legend(fontsize=8)
    ax[0].set_title("Hole-pass time")
    ax[1].bar(list(x), [(by[(s, "simplified")]["hole_triangles"] or 0) /
                        max(1.0, by[(s, "own")]["hole_triangles"] or 0) for s in names], 0.5,
              color="tab:green")
    ax[1].axhline(1, color="black", lw=0.8)
    ax[1].set_ylabel("hole triangles, simplified / own")
    ax[1].set_xticks(list(x))
    ax[1].set_xticklabels(names, rotation=35, ha="right", fontsize=8)
    dpsnr = max(abs((by[(s, "simplified")]["psnr_mean"] or 0) - (by[(s, "own")]["psnr_mean"] or 0))
                for s in names)
    ax[1].set_title("Triangles drawn (mean PSNR moves by at most %.1g dB)" % dpsnr, fontsize=10)
    fig.suptitle("walk --mode hybrid, 512x512, medians of %s rounds; %s, %s CPUs, LP_NUM_THREADS=%s" %
                 (meta["rounds"], meta["machine"], meta["cpus"], meta["lp_num_threads"]), fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "study.png"), dpi=110)


if __name__ == "__main__":
    main()
