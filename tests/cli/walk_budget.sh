#!/usr/bin/env bash
# walk --frame-budget-ms (issue #8, stable frame rate): the budget fields in
# report.json and the closing line on stdout; --pixel-age alone leaves the
# frames those of the default walk; bad budget values are usage errors that
# name the option.
# Usage: walk_budget.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
cat > "$tmp/path.json" <<'JSON'
{"width": 128, "height": 128, "fov_y_deg": 60, "near": 0.05, "far": 100, "up": [0, 1, 0],
 "keys": [{"eye": [0, 1.6, 4], "look_at": [0, 1.4, 0]}, {"eye": [1, 1.6, 1], "look_at": [0, 1.4, -3]}],
 "frames": 13, "keyframe_every": 6}
JSON
common=(walk --scene indoor:20k --path "$tmp/path.json" --strips 0 --quiet)
"$hw" "${common[@]}" --frame-budget-ms 40 --out "$tmp/b" >"$tmp/b.stdout" 2>"$tmp/b.stderr"
rc=$?; check "budget walk exits 0 ($(tail -2 "$tmp/b.stderr"))" test $rc -eq 0
r="$tmp/b/report.json"
for key in frame_budget_ms stale_after refreshed_pixels stale_pixels refresh_ms frames_refreshed \
           frame_interval_ms frame_interval_ms_p95_over_median budget_overruns \
           in_between_frame_ms in_between_frame_ms_p95_over_median refresh_cost_model; do
  check "summary has $key" python3 -c "
import json,sys; s=json.load(open('$r'))['summary']; sys.exit(0 if '$key' in s and s['$key'] is not None else 1)"
done
check "budget and stale-after recorded" python3 -c "
import json,sys; s=json.load(open('$r'))['summary']
sys.exit(0 if s['frame_budget_ms'] == 40 and s['stale_after'] == 2 and s['frame_pacing'] else 1)"
check "paced: every presented interval >= 40 ms" python3 -c "
import json,sys; f=json.load(open('$r'))['frames']
sys.exit(0 if len(f) == 13 and all(x['ms']['interval'] >= 40 for x in f) else 1)"
check "in-between frames report stale and refreshed pixels" python3 -c "
import json,sys; f=[x for x in json.load(open('$r'))['frames'] if not x['is_keyframe']]
sys.exit(0 if f and all('stale_pixels' in x and 'refreshed_pixels' in x and 'max_age' in x for x in f) else 1)"
check "stdout names the budget" grep -q "frame budget 40.0 ms" "$tmp/b.stdout"

# --pixel-age without a budget: the default walk's frames.
for v in default age; do
  extra=""; [ $v = age ] && extra="--pixel-age"
  # shellcheck disable=SC2086
  "$hw" "${common[@]}" --no-reference --save-frames $extra --out "$tmp/$v" >/dev/null 2>"$tmp/$v.stderr"
  rc=$?; check "$v walk exits 0" test $rc -eq 0
done
check "--pixel-age frames identical" diff -r "$tmp/default/frames" "$tmp/age/frames"
check "no budget line without a budget" test "$(grep -c 'frame budget' "$tmp/b.stdout")" -eq 1

# Bad values: usage errors (exit 2) naming the option and what was expected.
bad() {  # NAME REGEX ARGS...
  local name=$1 re=$2; shift 2
  "$hw" "${common[@]}" "$@" --out "$tmp/bad" >/dev/null 2>"$tmp/bad.stderr"
  local rc=$?
  check "$name exits 2 (got $rc)" test $rc -eq 2
  check "$name message ($(head -1 "$tmp/bad.stderr"))" grep -Eq -- "$re" "$tmp/bad.stderr"
  check "$name wrote nothing" test ! -e "$tmp/bad"
}
bad "--frame-budget-ms -1" '--frame-budget-ms.*expected milliseconds from 0.*-1' --frame-budget-ms -1
bad "--frame-budget-ms abc" '--frame-budget-ms.*expected milliseconds.*abc' --frame-budget-ms abc
bad "--stale-after 0" '--stale-after.*expected a whole number of frames from 1.*0' --frame-budget-ms 40 --stale-after 0
finish
