#!/usr/bin/env bash
# walk --frame-budget-ms (stable frame rate): the budget fields in
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
common=(walk --mode hybrid --scene indoor:20k --path "$tmp/path.json" --strips 0 --quiet)
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

# --frame-budget-ms auto: each frame's budget is the quantile (nearest rank)
# of the work without refresh of the last W in-between frames, recomputed here
# from the report's own per-frame ms; none until ceil(1/(1-q)) = 2 are known.
"$hw" "${common[@]}" --frame-budget-ms auto --frame-budget-quantile 0.5 --frame-budget-window 4 \
  --out "$tmp/auto" >"$tmp/auto.stdout" 2>"$tmp/auto.stderr"
rc=$?; check "auto budget walk exits 0 ($(tail -2 "$tmp/auto.stderr"))" test $rc -eq 0
r="$tmp/auto/report.json"
check "auto budget: mode, quantile, window and median budget recorded" python3 -c "
import json,sys; s=json.load(open('$r'))['summary']; a=s['frame_budget_auto']
sys.exit(0 if s['frame_budget_mode'] == 'auto' and a['quantile'] == 0.5 and a['window_frames'] == 4
         and a['frames_without_budget'] == 3 and s['frame_budget_ms'] == a['budget_ms']['median']
         and s['frame_budget_ms'] > 0 else 1)"
check "auto budget: each frame's budget is the median of the last 4 in-between works" python3 -c "
import json,math,sys; fr=json.load(open('$r'))['frames']
works=[]; bad=[]
for f in fr:
    b=f['budget_ms']
    if len(works) < 2:
        ok = b is None
    else:
        w=sorted(works[-4:]); ok = b is not None and abs(b - w[math.ceil(0.5*len(w)) - 1]) < 1e-9
    if not ok: bad.append((f['index'], b))
    if not f['is_keyframe']: works.append(f['ms']['frame'] - f['ms'].get('refresh', 0))
print(bad); sys.exit(0 if len(fr) == 13 and not bad else 1)"
check "auto budget: paced to each frame's budget" python3 -c "
import json,sys; fr=json.load(open('$r'))['frames']
sys.exit(0 if all(f['ms']['interval'] >= f['budget_ms'] for f in fr if f['budget_ms']) else 1)"
check "frame_times.png written (a PNG of more than 5 kB)" python3 -c "
import sys
d=open('$tmp/auto/frame_times.png','rb').read()
sys.exit(0 if d[:8]==b'\\x89PNG\\r\\n\\x1a\\n' and len(d) > 5000 else 1)"
check "stdout names the auto budget" grep -q "frame budget .* (auto)" "$tmp/auto.stdout"

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
bad "--frame-budget-ms fastest" '--frame-budget-ms.*expected milliseconds.*or .auto.*fastest' --frame-budget-ms fastest
bad "--frame-budget-quantile 0" '--frame-budget-quantile.*expected a quantile above 0 and at most 1.*0' --frame-budget-ms auto --frame-budget-quantile 0
bad "--frame-budget-quantile 1.5" '--frame-budget-quantile.*expected a quantile above 0 and at most 1.*1.5' --frame-budget-ms auto --frame-budget-quantile 1.5
bad "--frame-budget-window 0" '--frame-budget-window.*expected a whole number of frames from 1.*0' --frame-budget-ms auto --frame-budget-window 0
bad "--stale-after 0" '--stale-after.*expected a whole number of frames from 1.*0' --frame-budget-ms 40 --stale-after 0
finish
