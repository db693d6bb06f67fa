#!/usr/bin/env python3
"""Prints the tables of README.md from run.sh's output directory."""
import json, os, sys

out = sys.argv[1] if len(sys.argv) > 1 else "/tmp/qv"

print("| scene | path | keyframes | quads off → on | flagged off → on | worst px off → on | misfit splits |")
print("|---|---|---|---|---|---|---|")
cdir = os.path.join(out, "check")
tags = sorted({f[:-4] for f in os.listdir(cdir) if f.endswith("_off")})
for t in tags:
    try:
        a = json.load(open(os.path.join(cdir, t + "_off", "report.json")))
        b = json.load(open(os.path.join(cdir, t + "_on", "report.json")))
    except FileNotFoundError:
        print(f"| {t} | (missing) |"); continue
    sa, sb = a["summary"], b["summary"]
    splits = sum(k["misfit_splits"] for k in b["keyframes"])
    print(f"| {a['scene']['name']} | {a['path']} | {sa['keyframes']} | {sa['quads']} → {sb['quads']} "
          f"({100.0 * (sb['quads'] / max(1, sa['quads']) - 1):+.0f} %) | {sa['flagged']} → {sb['flagged']} "
          f"| {sa['max_error_px']:.2f} → {sb['max_error_px']:.2f} | {splits} |")

print()
print("| scene | PSNR median before → after | PSNR p5 | in-between ms median | frame / reference (median) | quads per keyframe (median) | LOD build ms (median) |")
print("|---|---|---|---|---|---|---|")
wdir = os.path.join(out, "walk")
for t in ["indoor_100k", "q3_oa_dm5", "torcs_forza", "outdoor_100k"]:
    try:
        a = json.load(open(os.path.join(wdir, t + "_before", "report.json")))["summary"]
        b = json.load(open(os.path.join(wdir, t + "_after", "report.json")))["summary"]
    except FileNotFoundError:
        print(f"| {t} | (missing) |"); continue
    f = lambda s, k, q: s[k][q]
    print(f"| {t} | {f(a,'psnr','median'):.2f} → {f(b,'psnr','median'):.2f} "
          f"| {f(a,'psnr','p5'):.2f} → {f(b,'psnr','p5'):.2f} "
          f"| {f(a,'in_between_frame_ms','median'):.2f} → {f(b,'in_between_frame_ms','median'):.2f} "
          f"| {f(a,'frame_over_reference','median'):.2f} → {f(b,'frame_over_reference','median'):.2f} "
          f"| {f(a,'quads_per_keyframe','median'):.0f} → {f(b,'quads_per_keyframe','median'):.0f} "
          f"| {f(a,'lod_build_ms','median'):.1f} → {f(b,'lod_build_ms','median'):.1f} |")
