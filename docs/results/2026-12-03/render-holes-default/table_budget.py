#!/usr/bin/env python3
"""Table of run_budget.sh: per path, holes off and on at each budget."""
import json, os, sys
d = sys.argv[1] if len(sys.argv) > 1 else "/tmp/rhb"
variants = [("off", "off"), ("b0.15", "0.15"), ("b0.3", "0.3"), ("b0", "no cap")]
def load(n):
    try: return json.load(open(os.path.join(d, n, "report.json")))["summary"]
    except (OSError, ValueError, KeyError): return None
def f(x, k="median"):
    v = x.get(k) if isinstance(x, dict) else None
    return "–" if v is None else f"{v:.2f}"
scenes = [l.strip() for l in open(os.path.join(d, "done")) if l.strip() != "ALL"]
print("| path | holes budget | geometry/warp/keyframe | frame/ref median | p95 | warped PSNR median | p5 |")
print("|---|---|---|---|---|---|---|")
for s in scenes:
    for v, label in variants:
        x = load(f"{s}_{v}")
        if not x: continue
        fm = "/".join(str(x["frames_by_mode"][k]) for k in ("geometry", "warp", "keyframe"))
        fo = x["frame_over_reference"]
        print(f"| {s} | {label} | {fm} | {f(fo)} | {f(fo, 'p95')} | {f(x['psnr'])} | {f(x['psnr'], 'p5')} |")
