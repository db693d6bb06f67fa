#!/usr/bin/env bash
# A short real walk: report.json carries the DESIGN.md fields, strips exist,
# and saved frames are non-trivial PNGs. Usage: walk_report.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
"$hw" walk --mode hybrid --scene indoor:20k --frames 12 --save-frames --strips 2 --out "$tmp/w" --quiet >"$tmp/stdout" 2>"$tmp/stderr"
code=$?
check "walk exits 0 (stderr: $(tail -3 "$tmp/stderr"))" test $code -eq 0
r="$tmp/w/report.json"
check report-exists test -s "$r"
for key in '"frames"' '"summary"' '"index"' '"is_keyframe"' '"psnr"' '"ssim"' \
           '"holes_before_fallback"' '"holes_after_fallback"' '"quads"' '"ms"' '"total"' \
           '"reference_ms"' '"triangles"' '"resolution"' '"tau"' '"depth_mode"' '"machine"' \
           '"median"' '"p95"'; do
  check "report has $key" grep -q "$key" "$r"
done
check "report counts 0 OpenGL errors" grep -q '"gl_errors": 0' "$r"
check "12 frames saved" test "$(ls "$tmp/w/frames" | wc -l)" -eq 12
check "12 hole masks saved" test "$(ls "$tmp/w/holes" | wc -l)" -eq 12
check "2 strips" test "$(ls "$tmp/w"/strip_*.png | wc -l)" -eq 2
check "no temporary files left" test -z "$(find "$tmp/w" -name '*.tmp-*')"
check "stdout summary line" grep -qE '^indoor:20k, 12 frames: [0-9]+ % warped, in-between [0-9.]+ dB \(p5 [0-9.]+\), frame [0-9.]+x the geometry frame \(median\), [0-9.]+x \(p95\)$' "$tmp/stdout"
check "stdout details: frames add up" grep -qE '^  frames: 12 = [0-9]+ warped \+ 0 drawn as geometry \+ [0-9]+ keyframe frames?$' "$tmp/stdout"
check "stdout details: PSNR median" grep -qE '^  warped frames: PSNR median [0-9.]+ dB' "$tmp/stdout"
# render and lod commands
"$hw" render --scene outdoor:20k --frames 3 --out "$tmp/r" >"$tmp/rout" 2>&1
rc=$?; check "render exits 0" test $rc -eq 0
check "render wrote 3 frames" test "$(ls "$tmp/r"/*.png | wc -l)" -eq 3
check "render.json" grep -q '"triangles"' "$tmp/r/render.json"
"$hw" lod --scene indoor:20k --frame 0 --tau 2^11 --out "$tmp/l/overlay.png" >"$tmp/lout" 2>&1
rc=$?; check "lod exits 0" test $rc -eq 0
check "lod overlay" test -s "$tmp/l/overlay.png"
check "lod stats" grep -q '"quads"' "$tmp/l/overlay.json"
"$hw" export-keyframes --scene indoor:20k --frames 12 --quiet --out "$tmp/e" >"$tmp/eout" 2>&1
rc=$?; check "export exits 0 ($(tail -2 "$tmp/eout"))" test $rc -eq 0
check "export cameras.json" grep -q '"world_from_camera"' "$tmp/e/cameras.json"
check "export keyframe png" test -s "$tmp/e/key_0000.png"
check "export keyframe depth" test -s "$tmp/e/key_0000.depth.pfm"
check "export last frame is a keyframe" test -s "$tmp/e/key_0011.png"
check "export in-between reference" test -s "$tmp/e/frame_0005.png"
finish
