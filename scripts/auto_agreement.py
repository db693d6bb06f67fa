#!/usr/bin/env python3
"""How reproducible `--mode auto` is: two report.json files of the same walk,
the fraction of frames drawn the same way, and what each run cost.

Prints the agreement of the two runs' frames[].mode, per frame, both as
"geometry" vs "warped" (warp and keyframe together) and as the exact mode,
then each run's summary.frames_by_mode and summary.frame_over_reference
median / p95. With --json, one JSON object instead (for tables).

Usage: scripts/auto_agreement.py [--json] RUN_A/report.json RUN_B/report.json
"""
import json
import sys


def load(path):
    try:
        with open(path) as f:
            r = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"auto_agreement: {path}: cannot read a report.json: {e}")
    frames = r.get("frames")
    if not isinstance(frames, list) or not all(isinstance(f, dict) and "mode" in f for f in frames):
        sys.exit(f"auto_agreement: {path}: expected frames[] with a 'mode' each")
    return r


def summarise(path, r):
    s = r.get("summary", {})
    fo = s.get("frame_over_reference") or {}
    modes = [f["mode"] for f in r["frames"]]
    return {
        "report": path,
        "frames": len(modes),
        "frames_by_mode": s.get("frames_by_mode"),
        "warped": sum(m != "geometry" for m in modes),
        "mode_switches": s.get("mode_switches"),
        "f_over_g_median": fo.get("median"),
        "f_over_g_p95": fo.get("p95"),
    }


def main(argv):
    as_json = "--json" in argv
    args = [a for a in argv if a != "--json"]
    if len(args) != 2:
        sys.exit(__doc__.strip().splitlines()[-1])
    ra, rb = load(args[0]), load(args[1])
    ma = [f["mode"] for f in ra["frames"]]
    mb = [f["mode"] for f in rb["frames"]]
    if len(ma) != len(mb):
        sys.exit(f"auto_agreement: the runs differ in length: {len(ma)} vs {len(mb)} frames "
                 "(expected the same walk twice)")
    n = max(1, len(ma))
    warped = sum((a == "geometry") == (b == "geometry") for a, b in zip(ma, mb)) / n
    exact = sum(a == b for a, b in zip(ma, mb)) / n
    out = {
        "frames": len(ma),
        "agreement_warped": warped,
        "agreement_exact": exact,
        "runs": [summarise(args[0], ra), summarise(args[1], rb)],
    }
    if as_json:
        print(json.dumps(out))
        return
    print(f"frames {len(ma)}: agreement geometry/warped {warped:.3f}, exact mode {exact:.3f}")
    for k, run in enumerate(out["runs"]):
        med, p95 = run["f_over_g_median"], run["f_over_g_p95"]
        fmt = lambda v: "null" if v is None else f"{v:.3f}"
        print(f"run {'AB'[k]}: frames_by_mode {json.dumps(run['frames_by_mode'])}, "
              f"warped {run['warped']}, mode_switches {run['mode_switches']}, "
              f"frame/geometry median {fmt(med)} p95 {fmt(p95)}  ({run['report']})")


if __name__ == "__main__":
    main(sys.argv[1:])
