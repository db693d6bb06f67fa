#!/usr/bin/env bash
# walk --primitives independent|indexed|shared draw the same pixels (byte-equal
# frames); --cull-background leaves background quads out and stays within
# 0.2 dB median PSNR of drawing them all.
# Usage: walk_primitives.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
common=(--scene indoor:20k --frames 23 --strips 0 --quiet)
for p in independent indexed shared; do
  "$hw" walk --mode hybrid "${common[@]}" --no-reference --save-frames --primitives "$p" --out "$tmp/$p" \
    >"$tmp/$p.out" 2>&1
  rc=$?; check "$p walk exits 0 ($(tail -1 "$tmp/$p.out"))" test $rc -eq 0
  check "  report names it" grep -q "\"primitives\": \"$p\"" "$tmp/$p/report.json"
done
for p in indexed shared; do
  same=1
  for f in "$tmp"/independent/frames/*.png; do
    cmp -s "$f" "$tmp/$p/frames/$(basename "$f")" || { echo "  $p differs: $(basename "$f")"; same=0; }
  done
  check "$p frames identical to independent (23)" test "$same" -eq 1 -a "$(ls "$tmp/$p/frames" | wc -l)" -eq 23
done
"$hw" walk --mode hybrid "${common[@]}" --out "$tmp/all" >/dev/null 2>&1
"$hw" walk --mode hybrid "${common[@]}" --cull-background --out "$tmp/cull" >/dev/null 2>&1
rc=$?; check "--cull-background walk exits 0" test $rc -eq 0
check "cull: some background quads left out, PSNR within 0.2 dB" python3 -c "
import json, sys
a = json.load(open('$tmp/all/report.json'))['summary']
c = json.load(open('$tmp/cull/report.json'))['summary']
print('  culled per frame max', c['background_quads_culled']['max'], 'median PSNR', c['psnr']['median'], 'vs', a['psnr']['median'])
sys.exit(0 if c['cull_background'] and not a['cull_background'] and c['background_quads_culled']['max'] > 0
         and abs(c['psnr']['median'] - a['psnr']['median']) <= 0.2 else 1)"
"$hw" walk --mode hybrid "${common[@]}" --primitives triangles --out "$tmp/bad" >"$tmp/bad.out" 2>&1
rc=$?; check "--primitives triangles: exit 2" test $rc -eq 2
check "  names the choices" grep -q "independent" "$tmp/bad.out"
finish
