#!/usr/bin/env bash
# view --async-keyframes ("stable frame rate"): keyframes rendered on
# a worker thread with a hidden window's context. Playing a path the viewer
# takes its keyframes from the worker (the first one waited for, as a load),
# writes per-frame statistics and frame-time percentiles, and its
# last frame is close to the synchronous viewer's (which keyframe a frame
# warps depends on when the worker finishes, so not pixel-equal by design;
# tests/gl/app_viewer_async_test.cpp checks the keyframes bit for bit and the
# lockstep frames pixel for pixel). With baked --keyframes it behaves as
# without the worker. Runs under Xvfb (scripts/test.sh runs CTest in xvfb-run).
# Usage: view_async.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
cd "$tmp"
cat > path.json <<'JSON'
{"width": 160, "height": 120, "fov_y_deg": 60, "near": 0.05, "far": 100, "up": [0, 1, 0],
 "keys": [{"eye": [0, 1.6, 4], "look_at": [0, 1.4, 0]}, {"eye": [1, 1.6, 1], "look_at": [0, 1.4, -3]}],
 "frames": 17, "keyframe_every": 4}
JSON
# Pinned to the paper's settings (every frame hybrid, keyframes rendered in the
# frame unless --async-keyframes): this compares the two ways of getting
# keyframes, not the auto choice.
common=(--scene indoor:20k --path path.json --play --no-hud --width 160 --height 120 --preset paper)

"$hw" view "${common[@]}" --exit-after 16 --screenshot sync.png --frame-stats sync.csv >sync.out 2>&1
rc=$?; check "sync view exits 0 ($(tail -1 sync.out))" test $rc -eq 0
"$hw" view "${common[@]}" --async-keyframes --exit-after 16 --screenshot async.png \
  --frame-stats async.csv >async.out 2>&1
rc=$?; check "async view exits 0 ($(tail -1 async.out))" test $rc -eq 0
cat async.out
check "names the worker" grep -q "keyframes rendered ahead on a worker thread" async.out
check "the first keyframe (at least) came from the worker" \
  grep -Eq "keyframes async: [1-9][0-9]* from the worker" async.out
check "keyframes built include the worker's (one count, one meaning)" python3 -c '
import re, sys
t = open("async.out").read()
b = re.search(r"(\d+) keyframes built \((\d+) on the worker thread\)", t)
w = re.search(r"keyframes async: (\d+) from the worker", t)
ok = b and w and int(b.group(2)) == int(w.group(1)) and int(b.group(1)) >= int(w.group(1)) > 0
print(b and b.group(0), w and w.group(0)); sys.exit(0 if ok else 1)'
check "summary has median / p95 / max frame ms" \
  grep -Eq "frame ms over frames 1..15: median [0-9.]+, p95 [0-9.]+, max [0-9.]+" async.out
check "sync summary counts its stalls" grep -Eq "keyframes in the frame: [1-9][0-9]* stalls" sync.out
check "frame stats: header + 16 rows" test "$(wc -l < async.csv)" -eq 17
check "  columns" grep -q "^frame,play_frame,ms,keyframe_ms,keyframe_rendered,keyframe_read,worker_keyframe,worker_requested,worker_waited,worker_stall,layers,work_ms,budget_ms,mode,hole_rects,hole_rects_over_budget,holes_ms$" async.csv
check "  frames 0..15 play path frames 0..15" \
  test "$(awk -F, 'NR > 1 && $1 == NR - 2 && $2 == NR - 2' async.csv | wc -l)" -eq 16
# (Whether a later frame is lost and renders one depends on the worker's speed.)
check "  async: the first frame waits for the worker's keyframe (loading), renders none" \
  test "$(awk -F, 'NR == 2 && $5 == 0 && $7 == 1 && $10 == 1' async.csv | wc -l)" -eq 1
check "  sync: keyframes rendered in frames, none from a worker" \
  test "$(awk -F, 'NR > 1 && $5 == 1' sync.csv | wc -l)" -ge 2 -a "$(awk -F, 'NR > 1 && $7 == 1' sync.csv | wc -l)" -eq 0
"$hw" compare async.png sync.png >cmp.out 2>&1
rc=$?; check "compare exits 0 ($(cat cmp.out))" test $rc -eq 0
echo "async vs sync, frame 15: $(cat cmp.out)"
check "async frame close to the sync one (PSNR >= 22 dB)" \
  awk '{for (i = 1; i < NF; i++) if ($i == "psnr_db") exit !($(i + 1) >= 22)}' cmp.out

# Baked keyframes: playing the baked path nothing changes with the worker.
"$hw" bake --scene indoor:20k --path path.json --out db --quiet >bake.out 2>&1
rc=$?; check "bake exits 0" test $rc -eq 0
"$hw" view --scene indoor:20k --path path.json --preset paper --keyframes db --play --exit-after 11 \
  --no-hud --screenshot baked.png >baked.out 2>&1
"$hw" view --scene indoor:20k --path path.json --preset paper --keyframes db --play --exit-after 11 \
  --no-hud --async-keyframes --screenshot baked_async.png >baked_async.out 2>&1
rc=$?; check "async view --keyframes exits 0 ($(tail -1 baked_async.out))" test $rc -eq 0
check "  every keyframe read from the database, none rendered" \
  grep -q "11 frames, 0 keyframes built (0 on the worker thread), 4 read from a database" baked_async.out
check "  nothing taken from the worker" grep -q "keyframes async: 0 from the worker" baked_async.out
"$hw" compare baked_async.png baked.png >cmpb.out 2>&1
check "  same frame as without the worker ($(cat cmpb.out))" grep -q "differing_pixels 0 of 19200" cmpb.out

# Usage errors.
"$hw" view --async-keyframes --keyframe-pacing sometimes --exit-after 1 >bad.out 2>&1
check "--keyframe-pacing sometimes: exit 2" test $? -eq 2
check "  names the option" grep -q -- "--keyframe-pacing" bad.out
env HW_GL_FAIL_SECOND=1 "$hw" view --async-keyframes --exit-after 1 >fail.out 2>&1
check "no worker context: exit 1" test $? -eq 1
check "  says so" grep -q "keyframe worker (--async-keyframes): cannot create a hidden window" fail.out
finish
