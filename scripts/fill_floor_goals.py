#!/usr/bin/env python3
"""Where the in-between frame stands against its fill-floor goals.

Runs each walk twice at the defaults (idle machine expected) with a fresh
folder of mode pins (OUT/pins): the first run chooses and pins its modes, the
second replays them, as a user's first and second run of a command would;
then a third time with --auto-pin off, whose modes against the first run's
say how far two measured runs agree. Then the viewer's --play on indoor:1M
at the defaults and as geometry. Writes
OUT/goals.json (every measured value, each goal with its target and whether
it is met) and OUT/goals.png (each goal's value over its target).

Usage: /usr/bin/python3 scripts/fill_floor_goals.py [--bin build/bin/hybridwalk]
           [--out DIR] [--no-viewer] [--plot-only]
The plot needs matplotlib (Debian python3-matplotlib, for /usr/bin/python3);
the viewer runs need xvfb-run (Debian xvfb).
"""
import argparse
import csv
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import time

WALKS = [
    # name, walk arguments
    ("indoor", ["--scene", "indoor"]),
    ("indoor:1M", ["--scene", "indoor:1M"]),
    ("q3:oa_dm5", ["--scene", "q3:oa_dm5", "--path", "paths/oa_dm5.json"]),
]


def median(v):
    return statistics.median(v) if v else None


def p95(v):
    if not v:
        return None
    v = sorted(v)
    return v[min(len(v) - 1, int(round(0.95 * (len(v) - 1))))]


def run(cmd, log, env=None):
    with open(log, "w") as f:
        rc = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT, env=env)
    if rc != 0:
        sys.exit("%s failed (exit %d); see %s" % (" ".join(cmd), rc, log))


def walk_summary(report):
    r = json.load(open(report))
    s = r["summary"]
    frames = r["frames"]
    warp = [f for f in frames if f.get("mode") == "warp"]
    fo = s.get("frame_over_reference") or {}
    floor = s.get("in_between_frame_over_floor") or {}
    by_mode = s.get("frames_by_mode") or {}
    in_between = s.get("in_between_frames") or 0
    return {
        "modes": [f.get("mode") for f in frames],
        "auto_pin": (s.get("auto_pin") or {}).get("state"),
        "frames_by_mode": by_mode,
        "in_between_frames": in_between,
        "warped_share_of_in_between": (by_mode.get("warp", 0) / in_between) if in_between else None,
        "frame_over_geometry_median": fo.get("median"),
        "frame_over_geometry_p95": fo.get("p95"),
        "in_between_over_floor_median": floor.get("median"),
        "floor_two_layers_ms": (s.get("floor_ms") or {}).get("two_layers"),
        "hole_pass_ms_median": median([f["ms"].get("render_holes", 0.0) for f in warp]),
        "hole_triangles_median": median([f.get("hole_triangles", 0) for f in warp]),
        "in_between_frame_ms_median": median([f["ms"]["frame"] for f in warp]),
        "warp_psnr_mean": statistics.mean([f["psnr"] for f in warp if f.get("psnr") is not None])
        if warp else None,
    }


def agreement(a, b):
    """Share of frames drawn the same way (geometry, or warped: warp/keyframe)."""
    warped = lambda m: m != "geometry"
    n = min(len(a), len(b))
    return sum(warped(x) == warped(y) for x, y in zip(a[:n], b[:n])) / n if n else None


def viewer_stats(binary, out, mode):
    stats = os.path.join(out, "view-%s.csv" % mode)
    run(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24 -noreset", binary, "view", "--scene",
         "indoor:1M", "--play", "--exit-after", "120", "--width", "512", "--height", "512",
         "--mode", mode, "--frame-stats", stats], os.path.join(out, "view-%s.log" % mode))
    ms = [float(row["ms"]) for row in csv.DictReader(open(stats)) if int(row["frame"]) >= 1]
    return {"median": median(ms), "p95": p95(ms), "frames": len(ms)}


def goal(name, value, target, better="below"):
    met = None if value is None else (value <= target if better == "below" else value >= target)
    return {"goal": name, "value": value, "target": target, "better": better, "met": met}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default="build/bin/hybridwalk")
    ap.add_argument("--out", default="out/fill-floor-goals")
    ap.add_argument("--no-viewer", action="store_true")
    ap.add_argument("--plot-only", action="store_true", help="redraw OUT/goals.png from OUT/goals.json")
    a = ap.parse_args()
    try:
        import matplotlib  # noqa: F401  (checked before the runs, used by plot())
    except ImportError:
        sys.exit("fill_floor_goals.py: the plot needs matplotlib: apt-get install python3-matplotlib, "
                 "then run it with /usr/bin/python3")
    if a.plot_only:
        plot(json.load(open(os.path.join(a.out, "goals.json")))["goals"],
             os.path.join(a.out, "goals.png"))
        return
    os.makedirs(a.out, exist_ok=True)
    pins = os.path.join(a.out, "pins")
    shutil.rmtree(pins, ignore_errors=True)
    env = dict(os.environ, HYBRIDWALK_PINS=pins)
    walks = {}
    for name, args in WALKS:
        runs = []
        for k, extra in ((1, []), (2, []), (3, ["--auto-pin", "off"])):
            d = os.path.join(a.out, "%s-%d" % (name.replace(":", "_"), k))
            print("walk %s, run %d %s" % (name, k, " ".join(extra)), flush=True)
            run([a.bin, "walk", *args, *extra, "--out", d], d + ".log", env)
            runs.append(walk_summary(os.path.join(d, "report.json")))
        walks[name] = {"runs": [{k: v for k, v in r.items() if k != "modes"} for r in runs[:2]],
                       "same_mode_share": agreement(runs[0]["modes"], runs[1]["modes"]),
                       "auto_pin": [r["auto_pin"] for r in runs],
                       "same_mode_share_measured": agreement(runs[0]["modes"], runs[2]["modes"])}
    viewer = None
    if not a.no_viewer:
        print("viewer, default and geometry", flush=True)
        viewer = {m: viewer_stats(a.bin, a.out, m) for m in ("auto", "geometry")}

    def worst(name, key, pick=max):
        vals = [r[key] for r in walks[name]["runs"] if r[key] is not None]
        return pick(vals) if vals else None

    goals = [
        goal("q3:oa_dm5 in-between / two-layer floor (median)",
             worst("q3:oa_dm5", "in_between_over_floor_median"), 2.0),
        goal("indoor:1M in-between / two-layer floor (median)",
             worst("indoor:1M", "in_between_over_floor_median"), 2.0),
        goal("indoor:1M frame / geometry median", worst("indoor:1M", "frame_over_geometry_median"),
             0.20),
        goal("indoor:1M frame / geometry p95", worst("indoor:1M", "frame_over_geometry_p95"), 0.35),
        goal("indoor:1M hole pass median (ms)", worst("indoor:1M", "hole_pass_ms_median"), 1.0),
        goal("indoor warped share of in-between frames",
             worst("indoor", "warped_share_of_in_between", min), 0.80, "above"),
        goal("indoor frame / geometry median", worst("indoor", "frame_over_geometry_median"), 0.6),
    ]
    for name in walks:
        goals.append(goal("%s same mode in two runs" % name, walks[name]["same_mode_share"], 0.90,
                          "above"))
    for name in walks:  # not a goal: how far two runs that both choose agree
        print("%-52s %8.3f  (runs 1 and 3, --auto-pin off)" % (
            "%s same mode, two measured runs" % name, walks[name]["same_mode_share_measured"]))
    if viewer:
        goals.append(goal("viewer --play indoor:1M p95 / geometry median",
                          viewer["auto"]["p95"] / viewer["geometry"]["median"], 0.25))
    result = {
        "machine": {"host": platform.node(), "cpus": os.cpu_count(),
                    "lp_num_threads": os.environ.get("LP_NUM_THREADS")},
        "date_utc": time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
        "walks": walks, "viewer": viewer, "goals": goals,
    }
    with open(os.path.join(a.out, "goals.json"), "w") as f:
        json.dump(result, f, indent=1)
    for g in goals:
        v = "—" if g["value"] is None else "%.3f" % g["value"]
        print("%-52s %8s  target %s %.2f  %s" % (g["goal"], v, "<=" if g["better"] == "below"
                                                  else ">=", g["target"],
                                                  {True: "met", False: "not met", None: "?"}[g["met"]]))
    plot(goals, os.path.join(a.out, "goals.png"))


def plot(goals, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    shown = [g for g in goals if g["value"] is not None]
    # Each goal as value / target for "below" goals and target / value for
    # "above" goals: <= 1 is met either way.
    ratio = [g["value"] / g["target"] if g["better"] == "below" else
             (g["target"] / g["value"] if g["value"] > 0 else 10.0) for g in shown]
    fig, ax = plt.subplots(figsize=(9, 0.45 * len(shown) + 1.4))
    colours = ["#2a9d3f" if r <= 1 else "#c0392b" for r in ratio]
    ax.barh(range(len(shown)), ratio, color=colours)
    ax.axvline(1.0, color="black", lw=1)
    ax.set_yticks(range(len(shown)))
    ax.set_yticklabels([g["goal"] for g in shown], fontsize=8)
    ax.invert_yaxis()
    for k, (g, r) in enumerate(zip(shown, ratio)):
        ax.text(r, k, " %.3g (target %s %.3g)" % (g["value"], "≤" if g["better"] == "below"
                                                    else "≥", g["target"]), va="center",
                fontsize=7)
    ax.set_xlabel("value / target (≤ 1: met; for ≥ goals, target / value)")
    ax.set_title("In-between frame goals: green met, red not (two runs each, worse run shown)",
                 fontsize=9)
    ax.set_xlim(0, max(ratio + [1.0]) * 1.45)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
