#!/usr/bin/env bash
# view --keyframes DB: playing the baked path, the viewer reads
# every keyframe from the database (none rendered) and shows the same frame as
# `walk --keyframes DB`; a database of another path or size is refused.
# Runs under Xvfb (scripts/test.sh runs CTest inside xvfb-run).
# Usage: view_keyframes.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
cd "$tmp"
cat > path.json <<'JSON'
{"width": 160, "height": 120, "fov_y_deg": 60, "near": 0.05, "far": 100, "up": [0, 1, 0],
 "keys": [{"eye": [0, 1.6, 4], "look_at": [0, 1.4, 0]}, {"eye": [1, 1.6, 1], "look_at": [0, 1.4, -3]}],
 "frames": 17, "keyframe_every": 4}
JSON
common=(--scene indoor:20k --path path.json)
"$hw" bake "${common[@]}" --out db --quiet >bake.out 2>&1
rc=$?; check "bake exits 0 ($(tail -1 bake.out))" test $rc -eq 0
"$hw" walk --mode hybrid --no-render-holes "${common[@]}" --keyframes db --save-frames --strips 0 \
  --no-reference --out walk --quiet >walk.out 2>&1
rc=$?; check "walk --keyframes exits 0 ($(tail -1 walk.out))" test $rc -eq 0

# 11 frames played: frames 0..10, the last between keyframes 8 and 12.
# Pinned to the paper's settings (every frame hybrid, keyframes in the frame):
# this tests the warped frames, not the auto choice.
"$hw" view "${common[@]}" --preset paper --keyframes db --play --exit-after 11 --no-hud --screenshot shot.png \
  >view.out 2>&1
rc=$?; check "view --keyframes exits 0 ($(tail -1 view.out))" test $rc -eq 0
check "window took the database's size" grep -q "160x120" view.out
check "no keyframe rendered, 4 read (0, 4, 8, 12)" \
  grep -q "11 frames, 0 keyframes built, 4 read from a database" view.out
check "last frame warped from two keyframes" grep -q "two keyframes warped" view.out
"$hw" compare shot.png walk/frames/0010.png --diff diff.png >cmp.out 2>&1
rc=$?; check "compare exits 0 ($(cat cmp.out))" test $rc -eq 0
echo "viewer frame 10 vs walk frame 10: $(cat cmp.out)"
check "viewer frame is the walk's, pixel for pixel" grep -q "differing_pixels 0 of 19200" cmp.out
"$hw" compare shot.png walk/frames/0000.png >cmp0.out 2>&1
check "  and it moved on from frame 0 ($(cat cmp0.out))" grep -Eq "differing_pixels [1-9]" cmp0.out
# The default preset warping every frame: the larger holes drawn by the
# geometry renderer, in the viewer as in the walk.
"$hw" walk --mode hybrid "${common[@]}" --keyframes db --save-frames --strips 0 --no-reference \
  --out walkh --quiet >walkh.out 2>&1
rc=$?; check "walk with holes drawn exits 0 ($(tail -1 walkh.out))" test $rc -eq 0
"$hw" view "${common[@]}" --mode hybrid --keyframes db --play --exit-after 11 --no-hud \
  --screenshot shoth.png >viewh.out 2>&1
rc=$?; check "view --mode hybrid exits 0 ($(tail -1 viewh.out))" test $rc -eq 0
"$hw" compare shoth.png walkh/frames/0010.png >cmph.out 2>&1
echo "viewer frame 10 vs walk frame 10, holes drawn: $(cat cmph.out)"
check "holes drawn: viewer frame is the walk's, pixel for pixel" grep -q "differing_pixels 0 of 19200" cmph.out
"$hw" compare shoth.png shot.png >cmpp.out 2>&1
check "  and differs from the frame without them ($(cat cmpp.out))" grep -Eq "differing_pixels [1-9]" cmpp.out
# Not playing: the viewer stands at the path's first camera, keyframe 0's,
# and takes the nearest baked keyframe (shown as is) instead of rendering one.
"$hw" view "${common[@]}" --preset paper --keyframes db --exit-after 3 --no-hud >still.out 2>&1
check "standing at keyframe 0: nothing built, keyframe 0 (and its neighbour) read" \
  grep -Eq "3 frames, 0 keyframes built, [12] read from a database; last frame: hybrid, a keyframe at this camera" still.out
# The same viewer without the database renders its own keyframes elsewhere.
"$hw" view "${common[@]}" --preset paper --play --exit-after 11 --no-hud --width 160 --height 120 >live.out 2>&1
check "without --keyframes keyframes are built" grep -Eq "11 frames, [1-9][0-9]* keyframes built, 0 read" live.out

# Refused: another size, another path.
"$hw" view "${common[@]}" --keyframes db --width 200 --exit-after 1 >bad1.out 2>&1
check "--width other than the database's: exit 1" test $? -eq 1
check "  names both sizes" grep -q -- "--width 200.*160x120" bad1.out
sed 's/"frames": 17/"frames": 18/' path.json > other.json
"$hw" view --scene indoor:20k --path other.json --keyframes db --exit-after 1 >bad2.out 2>&1
check "database of another path: exit 1" test $? -eq 1
check "  names path_hash" grep -q "path_hash" bad2.out
"$hw" view --scene indoor:20k --path path.json --keyframes nowhere --exit-after 1 >bad3.out 2>&1
check "missing database: exit 1" test $? -eq 1
check "  names the index" grep -q "nowhere" bad3.out
"$hw" compare shot.png walk/frames/0010.png nope.png >/dev/null 2>&1
check "compare with three images: exit 2 (usage)" test $? -eq 2
finish
