#!/usr/bin/env bash
# view --frame-budget-ms ("stable frame rate"): the viewer presents
# frames every budget ms (pacing only). Fixed: every frame after the first
# takes at least the budget. auto: each frame's budget is recomputed here
# from the per-frame work in --frame-stats (the quantile, nearest rank, of
# the last W frames' work, frame 0 excluded as the load; none until
# ceil(1/(1-q)) are known). Bad values are usage errors naming the option.
# Runs under Xvfb (scripts/test.sh runs CTest in xvfb-run).
# Usage: view_budget.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
cd "$tmp"
cat > path.json <<'JSON'
{"width": 160, "height": 120, "fov_y_deg": 60, "near": 0.05, "far": 100, "up": [0, 1, 0],
 "keys": [{"eye": [0, 1.6, 4], "look_at": [0, 1.4, 0]}, {"eye": [1, 1.6, 1], "look_at": [0, 1.4, -3]}],
 "frames": 25, "keyframe_every": 4}
JSON
# Pinned to the paper's settings (every frame hybrid; the auto budget run adds
# the worker): pacing is tested, not the auto choice.
common=(--scene indoor:20k --path path.json --play --no-hud --width 160 --height 120 --exit-after 24
        --preset paper)

"$hw" view "${common[@]}" --frame-budget-ms 40 --frame-stats fixed.csv >fixed.out 2>&1
rc=$?; check "fixed budget view exits 0 ($(tail -1 fixed.out))" test $rc -eq 0
check "  fixed: summary names the budget" grep -q "frame budget fixed: median 40.00 ms" fixed.out
check "  fixed: every shown frame took at least 40 ms, budget column 40" python3 -c "
import csv,sys
rows=list(csv.DictReader(open('fixed.csv')))[:-1]  # the last frame is not shown, not paced
sys.exit(0 if len(rows) == 23 and all(float(r['ms']) >= 40 and float(r['budget_ms']) == 40 for r in rows[1:]) else 1)"

"$hw" view "${common[@]}" --async-keyframes --frame-budget-ms auto --frame-budget-quantile 0.5 \
  --frame-budget-window 4 --frame-stats auto.csv >auto.out 2>&1
rc=$?; check "auto budget view exits 0 ($(tail -1 auto.out))" test $rc -eq 0
check "  auto: summary names the budget" grep -q "frame budget auto: median" auto.out
check "  auto: each frame's budget is the median of the last 4 frames' work" python3 -c "
import csv,math,sys
rows=list(csv.DictReader(open('auto.csv')))
works=[]; bad=[]
for r in rows:
    b=float(r['budget_ms'])
    if len(works) < 2:
        ok = b == 0
    else:
        w=sorted(works[-4:]); ok = abs(b - round(w[math.ceil(0.5*len(w)) - 1], 3)) <= 0.0015
    if not ok: bad.append((r['frame'], b))
    if int(r['frame']) >= 1: works.append(float(r['work_ms']))
print(bad); sys.exit(0 if len(rows) == 24 and not bad and any(float(r['budget_ms']) > 0 for r in rows) else 1)"
check "  auto: frames with a budget took at least it" python3 -c "
import csv,sys
rows=list(csv.DictReader(open('auto.csv')))[:-1]
sys.exit(0 if all(float(r['ms']) >= float(r['budget_ms']) - 0.002 for r in rows) else 1)"

bad() {  # NAME REGEX ARGS...
  local name=$1 re=$2; shift 2
  "$hw" view "${common[@]}" "$@" >bad.out 2>&1
  local rc=$?
  check "$name exits 2 (got $rc)" test $rc -eq 2
  check "$name message ($(head -1 bad.out))" grep -Eq -- "$re" bad.out
}
bad "--frame-budget-ms soon" "--frame-budget-ms.*expected milliseconds.*or 'auto'.*soon" --frame-budget-ms soon
bad "--frame-budget-quantile 2" "--frame-budget-quantile.*above 0 and at most 1.*2" --frame-budget-ms auto --frame-budget-quantile 2
finish
