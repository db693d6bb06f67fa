#!/usr/bin/env python3
"""Table of run_final.sh: default (holes drawn), default without holes, paper."""
import json, os, sys
d = sys.argv[1] if len(sys.argv) > 1 else "/tmp/rhf"
def load(n):
    try: return json.load(open(os.path.join(d, n, "report.json")))["summary"]
    except (OSError, ValueError, KeyError): return None
def f(x, k="median"):
    v = x.get(k) if isinstance(x, dict) else None
    return "–" if v is None else f"{v:.2f}"
scenes = [l.strip() for l in open(os.path.join(d, "done")) if l.strip() != "ALL"]
print("| path | settings | geometry/warp/keyframe | frame/ref median | p95 | warped PSNR median | p5 | in-between frame ms median | hole rectangles cut (mean per warped frame) |")
print("|---|---|---|---|---|---|---|---|---|")
for s in scenes:
    for v, label in (("default", "default (holes drawn)"), ("noholes", "default, --no-render-holes"), ("paper", "--preset paper")):
        x = load(f"{s}_{v}")
        if not x: continue
        fm = "/".join(str(x["frames_by_mode"][k]) for k in ("geometry", "warp", "keyframe"))
        fo = x["frame_over_reference"]
        cut = "–"
        try:
            fr = json.load(open(os.path.join(d, f"{s}_{v}", "report.json")))["frames"]
            c = [q["hole_rects_over_budget"] for q in fr if "hole_rects_over_budget" in q]
            if c: cut = f"{sum(c) / len(c):.1f}"
        except (OSError, ValueError, KeyError): pass
        print(f"| {s} | {label} | {fm} | {f(fo)} | {f(fo, 'p95')} | {f(x['psnr'])} | {f(x['psnr'], 'p5')} | {f(x['in_between_frame_ms'])} | {cut} |")
