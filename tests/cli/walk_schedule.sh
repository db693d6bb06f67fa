#!/usr/bin/env bash
# Error-driven keyframes end to end: walk --schedule adaptive records the
# planner in report.json, and a tiny schedule-study writes its files.
# Usage: walk_schedule.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
"$hw" walk --scene indoor:20k --frames 30 --schedule adaptive --target-psnr 24 --min-gap 3 \
  --max-gap 12 --strips 0 --out "$tmp/w" --quiet >"$tmp/stdout" 2>"$tmp/stderr"
rc=$?; check "adaptive walk exits 0 (stderr: $(tail -3 "$tmp/stderr"))" test $rc -eq 0
r="$tmp/w/report.json"
check "schedule recorded" grep -q '"keyframe_schedule": "adaptive"' "$r"
for key in '"planner"' '"plan_ms"' '"probe_render_ms"' '"target_psnr"' '"min_gap"' '"max_gap"' \
           '"predictor"' '"keyframe_frames"'; do
  check "report has $key" grep -q "$key" "$r"
done
check "stdout names the schedule" grep -q "adaptive schedule" "$tmp/stdout"
check "stderr reports planning time" grep -q "planned .* keyframes for 30 frames in" "$tmp/stderr"
# Gaps respected: consecutive keyframes 3..12 apart (the last gap may be shorter).
python3 - "$r" <<'PY'
import json, sys
k = json.load(open(sys.argv[1]))["summary"]["keyframe_frames"]
gaps = [b - a for a, b in zip(k, k[1:])]
ok = k[0] == 0 and k[-1] == 29 and all(3 <= g <= 12 for g in gaps[:-1]) and 1 <= gaps[-1] <= 12
sys.exit(0 if ok else 1)
PY
rc=$?; check "keyframe gaps within --min-gap/--max-gap" test $rc -eq 0
"$hw" schedule-study --scene indoor:20k --frames 24 --spacings 4,8 --reference-spacing 8 \
  --out "$tmp/s" --quiet >"$tmp/sout" 2>"$tmp/serr"
rc=$?; check "schedule-study exits 0 (stderr: $(tail -3 "$tmp/serr"))" test $rc -eq 0
for f in schedule.json runs.csv correlation.csv frames.csv schedule.png predictor.png index.html; do
  check "study wrote $f" test -s "$tmp/s/$f"
done
check "study has 2 fixed + 2 adaptive runs" test "$(grep -c '^adaptive' "$tmp/s/runs.csv")" -eq 2
check "study headline" grep -q '"keyframe_reduction"' "$tmp/s/schedule.json"
finish
