#!/usr/bin/env python3
"""Summarises run.sh's walks: per scene, the share of frames drawn the same way
(geometry, or from keyframes) in runs 1 and 2 (pinned: the second replays the
first) and in runs 1 and 3 (both measured), the frames whose PSNR differs
between runs 1 and 2, each run's frames by mode, frame /
geometry (median, p95), in-between PSNR median and keyframe stalls.
Writes results.csv, results.json and agreement.png beside this script.
Usage: /usr/bin/python3 summarise.py OUT
"""
import csv
import json
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
SCENES = ["indoor", "indoor:1M", "q3:oa_dm5", "q3:ps37ctf", "morse:tum_kitchen/tum_kitchen",
          "outdoor", "torcs:forza"]


def load(out, scene, run):
    name = scene.replace(":", "_").replace("/", "_")
    r = json.load(open(os.path.join(out, "%s-%d" % (name, run), "report.json")))
    s = r["summary"]
    fo = s.get("frame_over_reference") or {}
    return {
        "modes": ["g" if f["mode"] == "geometry" else "w" for f in r["frames"]],
        "frame_psnr": [f.get("psnr") for f in r["frames"]],
        "pin": (s.get("auto_pin") or {}).get("state"),
        "deviations": (s.get("auto_pin") or {}).get("deviations"),
        "by_mode": s["frames_by_mode"],
        "frame_over_geometry_median": fo.get("median"),
        "frame_over_geometry_p95": fo.get("p95"),
        "psnr_median": (s.get("psnr") or {}).get("median"),
        "keyframe_stalls": s.get("keyframe_stalls"),
        "machine": s.get("machine"),
    }


def same(a, b):
    n = min(len(a), len(b))
    return sum(x == y for x, y in zip(a, b)) / n if n else None


def main():
    out = sys.argv[1]
    rows = []
    machine = None
    for sc in SCENES:
        runs = [load(out, sc, k) for k in (1, 2, 3)]
        machine = machine or runs[0]["machine"]
        row = {"scene": sc, "frames": len(runs[0]["modes"]),
               "same_mode_pinned": same(runs[0]["modes"], runs[1]["modes"]),
               "same_mode_measured": same(runs[0]["modes"], runs[2]["modes"]),
               # frames whose PSNR differs between runs 1 and 2 (the same
               # image at the same camera gives the same PSNR)
               "frames_psnr_differs_pinned": sum(a != b for a, b in zip(runs[0]["frame_psnr"],
                                                                        runs[1]["frame_psnr"]))}
        for k, r in enumerate(runs, 1):
            row["run%d_pin" % k] = r["pin"]
            row["run%d_drawn_from_keyframes" % k] = r["by_mode"]["warp"] + r["by_mode"]["keyframe"]
            row["run%d_frame_over_geometry_median" % k] = r["frame_over_geometry_median"]
            row["run%d_frame_over_geometry_p95" % k] = r["frame_over_geometry_p95"]
            row["run%d_psnr_median" % k] = r["psnr_median"]
            row["run%d_keyframe_stalls" % k] = r["keyframe_stalls"]
            row["run%d_pin_deviations" % k] = r["deviations"]
        rows.append(row)
    with open(os.path.join(here, "results.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    json.dump({"machine": machine, "scenes": rows}, open(os.path.join(here, "results.json"), "w"),
              indent=1)
    for r in rows:
        print("%-32s psnr differs on %d frames" % (r["scene"], r["frames_psnr_differs_pinned"]))
        print("%-32s pinned %.3f  measured %.3f  f/g median %s %s %s" % (
            r["scene"], r["same_mode_pinned"], r["same_mode_measured"],
            r["run1_frame_over_geometry_median"], r["run2_frame_over_geometry_median"],
            r["run3_frame_over_geometry_median"]))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(8, 3.6))
    x = range(len(rows))
    ax.bar([i - 0.2 for i in x], [r["same_mode_measured"] for r in rows], 0.4,
           label="two measured runs (--auto-pin off)", color="#c0392b")
    ax.bar([i + 0.2 for i in x], [r["same_mode_pinned"] for r in rows], 0.4,
           label="measured, then replayed (--auto-pin use, the default)", color="#2a9d3f")
    ax.axhline(0.9, color="black", lw=0.8, ls="--")
    ax.text(len(rows) - 0.45, 0.86, "0.9", fontsize=7, ha="right", va="bottom")
    ax.set_xticks(list(x))
    ax.set_xticklabels([r["scene"].split("/")[0] for r in rows], fontsize=8, rotation=15)
    ax.set_ylabel("share of frames drawn the same way")
    ax.set_ylim(0, 1.3)
    ax.legend(fontsize=7, loc="upper center", ncol=2)
    ax.set_title("--mode auto, two runs of one walk: geometry or from keyframes, frame by frame "
                 "(512², defaults)", fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(here, "agreement.png"), dpi=110)


if __name__ == "__main__":
    main()
