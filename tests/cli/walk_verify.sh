#!/usr/bin/env bash
# The verified planner: walk --verify-rounds walks the planned
# segments not measured yet, replans on the measured frames, and walks the
# fewest keyframes whose median measured frames alone guarantee. Checked
# against the walk that runs it: at least the planner's measured count of its
# frames reach the target (good_frames, more than half), so the median does;
# the rounds add up, and the schedule is within the gaps. (That a measured
# frame is the walk's own, bit for bit: bench_measure_segments_test.) Usage: walk_verify.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
common=(--scene indoor:20k --frames 40 --strips 0 --quiet)
plan=(--schedule adaptive --plan-by walk-median --predictor probe-psnr --max-gap 12
      --calibrate-spacing 6 --target-psnr fixed:10)
"$hw" walk --mode hybrid "${common[@]}" "${plan[@]}" --calibration-window 3 --verify-rounds 12 --verify-optimism 0.5 \
  --out "$tmp/v" >"$tmp/v.out" 2>"$tmp/v.err"
rc=$?; check "verified walk exits 0 ($(tail -2 "$tmp/v.err"))" test $rc -eq 0
check "verify.png written" test -s "$tmp/v/verify.png"
check "stderr reports the verified plan" grep -q "verified: .* keyframes (planned .*) after .* rounds" "$tmp/v.err"
"$hw" walk --mode hybrid "${common[@]}" "${plan[@]}" --verify-rounds 0 --out "$tmp/off" >"$tmp/off.out" 2>&1
rc=$?; check "--verify-rounds 0 exits 0" test $rc -eq 0
python3 - "$tmp" <<'PY'
import json, sys
t = sys.argv[1]
rep = json.load(open(t + "/v/report.json"))
s = rep["summary"]
p = s["planner"]
v = p["verify"]
bad = []
def expect(cond, what):
    if not cond: bad.append(what)
target = p["target_psnr"]
k = s["keyframe_frames"]
expect(v["keyframes"] == len(k) == s["keyframes"], "verify.keyframes %s = the walk's %d" % (v["keyframes"], len(k)))
expect(k[0] == 0 and k[-1] == 39 and all(2 <= b - a <= 12 for a, b in zip(k, k[1:-1])) and 1 <= k[-1] - k[-2] <= 12,
       "gaps within 2..12: %s" % k)
expect(v["max_rounds"] == 12 and v["optimism_db"] == 0.5, "options recorded: %s" % v)
expect(v["median_guaranteed"], "a guaranteed schedule exists (fixed-10's segments reach the target)")
inb = [f for f in rep["frames"] if not f["is_keyframe"]]
vals = [f["psnr"] if f["psnr"] is not None else 99.0 for f in inb]
good = sum(1 for x in vals if x >= target)
expect(good >= v["good_frames"], "the walk's frames >= target %d, at least the planner's measured count %s" % (good, v["good_frames"]))
expect(2 * v["good_frames"] > len(vals), "measured frames alone: more than half reach the target (%s of %d)" % (v["good_frames"], len(vals)))
expect(s["psnr"]["median"] >= target - 1e-9, "median %.4f >= target %.4f" % (s["psnr"]["median"], target))
r = v["rounds"]
expect(len(r) >= 1 and r[-1]["frames_measured"] == 0, "the last round measures nothing")
expect(sum(x["frames_measured"] for x in r) == v["frames_measured"], "rounds' frames add up to frames_measured")
expect(all(x["frames_measured"] > 0 for x in r[:-1]), "every earlier round measured something")
expect(v["converged"] or len(r) - 1 == 12, "not converged only when the 12 rounds ran out")
expect(all(x["guaranteed_keyframes"] >= r[-1]["guaranteed_keyframes"] or x["guaranteed_keyframes"] == 0 for x in r),
       "the measured schedule never gets longer over the rounds")
expect(r[-1]["guaranteed_keyframes"] == len(k), "the walked schedule is the last round's guaranteed one")
expect(v["planned_keyframes"] == r[0]["keyframes"] or r[0]["guaranteed_keyframes"] > 0,
       "round 0 plans like the predictor (or aims below the calibration's measured schedule)")
off = json.load(open(t + "/off/report.json"))["summary"]["planner"]
expect(off["verify"] is None, "--verify-rounds 0: verify null")
for b in bad: print("FAIL", b)
sys.exit(1 if bad else 0)
PY
rc=$?; check "report and verified plan agree" test $rc -eq 0
finish
