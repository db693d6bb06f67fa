#!/usr/bin/env bash
# walk --async-keyframes: the same frames as the synchronous walk, byte for
# byte, and the frame-time fields in the summary.
# Usage: walk_async.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
for mode in sync async; do
  extra="--sync-keyframes"
  [ "$mode" = async ] && extra="--async-keyframes --keyframe-cache-mb 16"
  # shellcheck disable=SC2086
  "$hw" walk --mode hybrid --scene indoor:20k --frames 23 --save-frames --strips 0 --no-reference $extra \
    --out "$tmp/$mode" --quiet >"$tmp/$mode.stdout" 2>"$tmp/$mode.stderr"
  rc=$?; check "$mode walk exits 0 ($(tail -2 "$tmp/$mode.stderr"))" test $rc -eq 0
done
check "23 frames each" test "$(ls "$tmp/async/frames" | wc -l)" -eq 23
same=1
for f in "$tmp"/sync/frames/*.png; do
  cmp -s "$f" "$tmp/async/frames/$(basename "$f")" || { echo "  differs: $(basename "$f")"; same=0; }
done
check "async frames identical to sync" test $same -eq 1
r="$tmp/async/report.json"
for key in '"frame_ms"' '"frame_ms_p95_over_median"' '"in_between_frame_ms"' \
           '"in_between_frame_ms_p95_over_median"' '"keyframe_stalls"' '"keyframe_stall_ms"' \
           '"keyframe_warmup_ms"' '"keyframe_cache_peak_mb"' '"keyframe_pacing"' '"keyframe_wait"'; do
  check "report has $key" grep -q "$key" "$r"
done
check "acquisition is async" grep -q '"keyframe_acquisition": "async"' "$r"
check "sync report says sync" grep -q '"keyframe_acquisition": "sync"' "$tmp/sync/report.json"
check "stdout's keyframe stalls are the report's keyframe_stalls" python3 -c "
import json, re, sys
m = re.search(r'(\d+) keyframe stalls? ', open('$tmp/async.stdout').read())
s = json.load(open('$r'))['summary']
print(m and m.group(1), s['keyframe_stalls']); sys.exit(0 if m and int(m.group(1)) == s['keyframe_stalls'] else 1)"
check "cache stayed within 16 MiB" python3 -c "
import json,sys; s=json.load(open('$r'))['summary']; sys.exit(0 if s['keyframe_cache_peak_mb'] <= 16 else 1)"
check "per-frame keyframe worker ms: on every frame, not negative, summing to at most the worker's busy time and to more than 0" python3 -c "
import json,sys; r=json.load(open('$r')); s=r['summary']
w=[f['ms'].get('keyframe_worker') for f in r['frames']]
ok = all(x is not None and x >= 0 for x in w) and 0 < sum(w) <= s['keyframe_worker_busy_ms'] + 1e-6
print(sum(w), s['keyframe_worker_busy_ms']); sys.exit(0 if ok else 1)"
check "sync frames have no keyframe worker ms" python3 -c "
import json,sys; r=json.load(open('$tmp/sync/report.json'))
sys.exit(0 if all('keyframe_worker' not in f['ms'] for f in r['frames']) else 1)"
finish
