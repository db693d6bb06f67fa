#!/usr/bin/env python3
"""Table of the run.sh walks: per scene and mode, render-holes off -> on."""
import json, os, sys
d = sys.argv[1] if len(sys.argv) > 1 else "/tmp/rhd"
def load(n):
    try: return json.load(open(os.path.join(d, n, "report.json")))["summary"]
    except (OSError, ValueError, KeyError): return None
def f(x, k="median", nd=2):
    v = x.get(k) if isinstance(x, dict) else None
    return "–" if v is None else f"{v:.{nd}f}"
scenes = [l.strip() for l in open(os.path.join(d, "done")) if l.strip() != "ALL"]
print("| scene | mode | geometry/warp/keyframe | frame/ref median | p95 | warped PSNR median | p5 | in-between ms median |")
print("|---|---|---|---|---|---|---|---|")
for s in scenes:
    for mode in ("auto", "hybrid"):
        a, b = load(f"{s}_{mode}_no-render-holes"), load(f"{s}_{mode}_render-holes")
        if not a or not b: continue
        def both(get): return f"{get(a)} → {get(b)}"
        fm = lambda x: "/".join(str(x["frames_by_mode"][k]) for k in ("geometry", "warp", "keyframe"))
        print(f"| {s} | {mode} | {both(fm)} | {both(lambda x: f(x['frame_over_reference']))} | "
              f"{both(lambda x: f(x['frame_over_reference'], 'p95'))} | {both(lambda x: f(x['psnr']))} | "
              f"{both(lambda x: f(x['psnr'], 'p5'))} | {both(lambda x: f(x['in_between_ms']))} |")
