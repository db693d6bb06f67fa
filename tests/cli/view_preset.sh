#!/usr/bin/env bash
# view --preset default|paper and the default --mode auto: every 10 frames
# the viewer draws hybrid or geometry, whichever this session measured
# cheaper. A 20-triangle room draws in a fraction of a warp's time, so the
# default viewer switches to geometry and its last frame is exactly the
# geometry viewer's; indoor:1M draws in ~100 ms against a few ms for a warp
# at 320x240, so it stays hybrid (its only geometry frames are single probes).
# --preset paper warps every frame; an option departing from the paper is a
# usage error (exit 2) naming it; --help is grouped. Runs under Xvfb
# (scripts/test.sh runs CTest in xvfb-run).
# Usage: view_preset.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
cd "$tmp"
# A 10 x 3 x 10 room (faces wound to be seen from inside) with a pillar.
cat > room.obj <<'OBJ'
v -5 0 -5
v 5 0 -5
v 5 0 5
v -5 0 5
v -5 3 -5
v 5 3 -5
v 5 3 5
v -5 3 5
v -1 0 -1
v 1 0 -1
v 1 0 1
v -1 0 1
v -1 3 -1
v 1 3 -1
v 1 3 1
v -1 3 1
f 4 3 2 1
f 5 6 7 8
f 2 6 5 1
f 3 7 6 2
f 4 8 7 3
f 1 5 8 4
f 9 10 14 13
f 10 11 15 14
f 11 12 16 15
f 12 9 13 16
OBJ
cat > room.json <<'JSON'
{"width": 320, "height": 240, "fov_y_deg": 60, "near": 0.05, "far": 100, "up": [0, 1, 0],
 "keys": [{"eye": [-4, 1.6, 4], "look_at": [0, 1.4, 0]}, {"eye": [4, 1.6, 4], "look_at": [0, 1.4, 0]},
          {"eye": [4, 1.6, -4], "look_at": [0, 1.4, 0]}],
 "frames": 60, "keyframe_every": 10}
JSON
# Distinct colours and the largest share of one colour in an 8-bit RGB(A) PNG.
png_colours() {
  python3 - "$1" <<'PY'
import struct, sys, zlib
data = open(sys.argv[1], 'rb').read()
pos, idat, w, h, bpp = 8, b'', 0, 0, 0
while pos < len(data):
    n, kind = struct.unpack('>I4s', data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    if kind == b'IHDR':
        w, h, depth, ctype = struct.unpack('>IIBB', body[:10])
        assert depth == 8 and ctype in (2, 6), (depth, ctype)
        bpp = 3 if ctype == 2 else 4
    elif kind == b'IDAT':
        idat += body
    pos += 12 + n
raw, stride = zlib.decompress(idat), w * bpp
prev, counts = bytearray(stride), {}
for y in range(h):
    f, row = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for i in range(stride):
        a = row[i - bpp] if i >= bpp else 0
        b, c = prev[i], prev[i - bpp] if i >= bpp else 0
        p = a + b - c
        pred = [0, a, b, (a + b) // 2,
                a if abs(p - a) <= min(abs(p - b), abs(p - c)) else (b if abs(p - b) <= abs(p - c) else c)][f]
        row[i] = (row[i] + pred) & 255
    for x in range(0, stride, bpp):
        k = bytes(row[x:x + 3])
        counts[k] = counts.get(k, 0) + 1
    prev = row
print(len(counts), max(counts.values()) / (w * h))
PY
}
room1=(--scene room.obj --path room.json --play --no-hud --width 320 --height 240)
# Auto decides every 10 frames; a probe frame measures the geometry at each
# choice until three renders are known (the median of three, so that one
# render slowed by other work on the machine does not decide), then one
# choice in four: the room switches by frame 39, or with a slow probe among
# the first three by frame 79.
room=("${room1[@]}" --exit-after 100)

# The default: --mode auto, and the room switches to geometry.
"$hw" view "${room[@]}" --frame-stats auto.csv --screenshot auto.png >auto.out 2>&1
rc=$?; check "default view exits 0 ($(tail -1 auto.out))" test $rc -eq 0
grep "mode auto" auto.out
check "the default preset: mode auto, tau-px, region-local, merged strips" \
  grep -q "mode auto, tau-px [0-9.]* (region-local planarity, merged strips)" auto.out
check "  keyframes built ahead on the worker" grep -q "keyframes rendered ahead on a worker thread" auto.out
# At a choice (every 10 frames) or earlier, when the hybrid frames after a
# choice all cost more than drawing (the segment is given up).
check "room: auto chose geometry" grep -Eq "auto chose geometry from frame [0-9]+\b" auto.out
check "  the message says so" \
  grep -Eq "auto: geometry \((cheaper now|hybrid frames cost more); from frame" auto.out
check "  the last frame was drawn as geometry" grep -q "last frame: geometry" auto.out
check "  frame stats: a mode column, the last 10 frames geometry" \
  test "$(tail -10 auto.csv | awk -F, '$14 == "geometry"' | wc -l)" -eq 10
check "  and warped frames before the choice" \
  test "$(awk -F, 'NR > 1 && NR <= 11 && $14 == "warp"' auto.csv | wc -l)" -ge 5
"$hw" view "${room[@]}" --mode geometry --screenshot geometry.png >geometry.out 2>&1
"$hw" compare auto.png geometry.png >cmp.out 2>&1
check "  its last frame is the geometry viewer's, pixel for pixel ($(cat cmp.out))" \
  grep -q "differing_pixels 0 of 76800" cmp.out
read -r colours share < <(png_colours auto.png)
echo "room screenshot: $colours colours, the commonest on a fraction $share of the pixels"
check "  screenshot not blank (>= 100 colours, none on half the pixels)" \
  awk -v c="$colours" -v s="$share" 'BEGIN { exit !(c >= 100 && s < 0.5) }'

# The paper's settings: every frame hybrid, whatever it costs.
"$hw" view "${room[@]}" --preset paper --frame-stats paper.csv --screenshot paper.png >paper.out 2>&1
rc=$?; check "--preset paper exits 0 ($(tail -1 paper.out))" test $rc -eq 0
check "  mode hybrid, tau 2048, stencil, no merging" \
  grep -q "mode hybrid, tau 2048 (stencil planarity)" paper.out
check "  no geometry frame" grep -q "mode hybrid: 0 frames drawn as geometry" paper.out
check "  none in the frame stats either" test "$(awk -F, '$14 == "geometry"' paper.csv | wc -l)" -eq 0
check "  keyframes rendered in the frame (no worker)" grep -q "keyframes in the frame:" paper.out
check "  --mode hybrid (the paper's) is no contradiction" \
  "$hw" view "${room1[@]}" --preset paper --mode hybrid --exit-after 2
check "  nor --tau" "$hw" view "${room1[@]}" --preset paper --tau 2^12 --exit-after 2

# A heavy scene stays hybrid under the default.
"$hw" view --scene indoor:1M --play --no-hud --width 320 --height 240 --exit-after 40 \
  --frame-stats heavy.csv --screenshot heavy.png >heavy.out 2>&1
rc=$?; check "indoor:1M exits 0 ($(tail -1 heavy.out))" test $rc -eq 0
grep "mode auto" heavy.out
check "indoor:1M: auto never chose geometry" grep -q "auto never chose geometry" heavy.out
check "  its geometry frames are single probes" \
  test "$(awk -F, 'NR > 2 && $14 == "geometry" && last == "geometry" { n++ } { last = $14 } END { print n + 0 }' heavy.csv)" -eq 0
check "  last frame hybrid" grep -q "last frame: hybrid" heavy.out
read -r colours share < <(png_colours heavy.png)
check "  screenshot not blank ($colours colours, commonest $share)" \
  awk -v c="$colours" -v s="$share" 'BEGIN { exit !(c >= 500 && s < 0.5) }'

# Usage errors: exit 2 before a window opens, naming the option.
bad() {  # NAME REGEX ARGS...
  local name=$1 re=$2; shift 2
  "$hw" view "$@" --exit-after 1 >bad.out 2>&1
  local rc=$?
  check "$name exits 2 (got $rc)" test $rc -eq 2
  check "$name message ($(head -1 bad.out))" grep -Eq -- "$re" bad.out
}
bad "--preset paper --tau-px 0.1" "--tau-px: contradicts --preset paper" --preset paper --tau-px 0.1
bad "--preset paper --mode auto" "--mode: contradicts --preset paper \(the paper's: hybrid\)" \
  --preset paper --mode auto
bad "--preset paper --geometry" "--geometry: contradicts --preset paper" --preset paper --geometry
bad "--preset paper --merge-strips" "--merge-strips: contradicts --preset paper" --preset paper --merge-strips
bad "--preset paper --planarity region-local" "--planarity: contradicts --preset paper" \
  --preset paper --planarity region-local
bad "--preset best" "--preset.*best.*default,paper" --preset best
bad "--geometry --mode auto" "--geometry.*excludes.*--mode|--mode.*excludes.*--geometry" --geometry --mode auto
bad "--tau with --tau-px" "--tau.*excludes|excludes.*--tau" --tau 2^11 --tau-px 0.1

# --help: grouped like walk's, defaults from the default preset.
"$hw" view --help >help.out 2>&1
for g in "Essentials:" "Level of detail:" "Keyframes:" "Timing:"; do
  check "help has the group $g" grep -q "^$g" help.out
done
check "help: --mode defaults to auto" grep -q -- "--mode TEXT:{auto,hybrid,geometry}=auto" help.out
check "help: --preset defaults to default" grep -q -- "--preset TEXT:{default,paper}=default" help.out
check "help: the window size in pixels" grep -q "Window width, pixels" help.out
finish
