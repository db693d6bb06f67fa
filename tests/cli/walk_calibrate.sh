#!/usr/bin/env bash
# The planner calibrated on the scene: walk --calibrate-spacing
# walks fixed schedules first, refits the predictor to their measured PSNRs
# and plans with it; --target-psnr fixed:G takes a calibration walk's median.
# Checked against the walk itself: the calibration walk every 10 frames has
# the median of the ordinary fixed walk (the built-in path's keyframe_every
# is 10), the report's residual spread is the CSV's, and the planner's
# uncertainty is that spread unless given; with --calibration-window the
# offsets along the path and what they leave are recomputed from the CSV.
# Usage: walk_calibrate.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
common=(--scene indoor:20k --frames 40 --strips 0 --quiet)
"$hw" walk --mode hybrid "${common[@]}" --out "$tmp/fixed" >"$tmp/fixed.out" 2>&1
rc=$?; check "fixed walk exits 0 ($(tail -2 "$tmp/fixed.out"))" test $rc -eq 0
plan=(--schedule adaptive --plan-by walk-median --predictor probe-psnr --max-gap 12)
"$hw" walk --mode hybrid "${common[@]}" "${plan[@]}" --calibrate-spacing 6 --target-psnr fixed:10 \
  --out "$tmp/cal" >"$tmp/cal.out" 2>"$tmp/cal.err"
rc=$?; check "calibrated walk exits 0 ($(tail -2 "$tmp/cal.err"))" test $rc -eq 0
check "calibration.csv written" test -s "$tmp/cal/calibration.csv"
check "calibration.png written" test -s "$tmp/cal/calibration.png"
check "planned.png written" test -s "$tmp/cal/planned.png"
check "stderr reports the calibration" grep -q "calibrated probe-psnr on .* in-between frames: residual sd" "$tmp/cal.err"
"$hw" walk --mode hybrid "${common[@]}" "${plan[@]}" --calibrate-spacing 6 --target-psnr 30 --plan-uncertainty 0 \
  --out "$tmp/u0" >"$tmp/u0.out" 2>&1
rc=$?; check "calibrated walk with --plan-uncertainty 0 exits 0" test $rc -eq 0
"$hw" walk --mode hybrid "${common[@]}" "${plan[@]}" --target-psnr 30 --out "$tmp/plain" >"$tmp/plain.out" 2>&1
rc=$?; check "uncalibrated walk exits 0" test $rc -eq 0
"$hw" walk --mode hybrid "${common[@]}" "${plan[@]}" --calibrate-spacing 6 --target-psnr fixed:10 --calibration-window 3 \
  --out "$tmp/win" >"$tmp/win.out" 2>"$tmp/win.err"
rc=$?; check "calibrated walk with --calibration-window 3 exits 0 ($(tail -2 "$tmp/win.err"))" test $rc -eq 0
check "stderr reports what the window leaves" grep -q "along the path (3 frames): .* dB left" "$tmp/win.err"
python3 - "$tmp" <<'PY'
import csv, json, math, sys
t = sys.argv[1]
fixed = json.load(open(t + "/fixed/report.json"))["summary"]
s = json.load(open(t + "/cal/report.json"))["summary"]
p = s["planner"]
c = p["calibration"]
bad = []
def expect(cond, what):
    if not cond: bad.append(what)
walks = {w["spacing"]: w for w in c["walks"]}
expect(sorted(walks) == [6, 10], "walks every 6 and 10 frames, got %s" % sorted(walks))
expect(walks[10]["keyframes"] == fixed["keyframes"], "every-10 walk has the fixed walk's keyframes")
expect(abs(walks[10]["psnr_median"] - fixed["psnr"]["median"]) < 1e-9,
       "every-10 median %s = fixed walk's %s" % (walks[10]["psnr_median"], fixed["psnr"]["median"]))
expect(p["target_psnr"] == walks[10]["psnr_median"], "target = the every-10 median")
expect(p["target_source"] == "fixed:10", "target_source fixed:10, got %s" % p["target_source"])
rows = list(csv.DictReader(open(t + "/cal/calibration.csv")))
# (No frame of this path is identical to its reference, so every in-between
# frame is a sample.)
expect(len(rows) == c["samples"] == sum(w["in_between"] for w in c["walks"]),
       "CSV rows %d = samples %d = in-between frames" % (len(rows), c["samples"]))
expect(all(int(r["k0"]) < int(r["frame"]) < int(r["k1"]) for r in rows), "k0 < frame < k1")
expect(all(int(r["k1"]) - int(r["k0"]) <= int(r["spacing"]) for r in rows), "segments within the spacing")
res = [float(r["psnr"]) - float(r["predicted"]) for r in rows]
sd = math.sqrt(sum(x * x for x in res) / (len(res) - 2))  # probe-psnr: 2 coefficients
expect(abs(sd - c["residual_std_db"]) < 1e-3, "residual sd from the CSV %.4f = report %.4f" % (sd, c["residual_std_db"]))
expect(abs(sum(res) / len(res)) < 1e-3, "least squares: residuals average 0 (%.5f)" % (sum(res) / len(res)))
expect(p["uncertainty"] == "empirical" and p["uncertainty_db"] == c["residual_std_db"],
       "auto uncertainty: the calibration's residuals (%s)" % p["uncertainty"])
# planned.csv: every in-between frame of the schedule, measured = the report's.
frames = {f["index"]: f for f in json.load(open(t + "/cal/report.json"))["frames"]}
pl = list(csv.DictReader(open(t + "/cal/planned.csv")))
k = s["keyframe_frames"]
expect([int(r["frame"]) for r in pl] == [f for a, b in zip(k, k[1:]) for f in range(a + 1, b)],
       "planned.csv lists every in-between frame of the schedule")
expect(all(abs(float(r["measured"]) - frames[int(r["frame"])]["psnr"]) < 1e-3 for r in pl),
       "planned.csv measured = the report's frame PSNR")
pm = sorted(float(r["predicted"]) for r in pl)
med = pm[len(pm) // 2] if len(pm) % 2 else 0.5 * (pm[len(pm) // 2 - 1] + pm[len(pm) // 2])
expect(abs(med - p["predicted_psnr_median"]) < 1e-3, "predicted median %.4f = report %.4f" % (med, p["predicted_psnr_median"]))
expect(p["fit"]["slope"] < 0, "a larger probe error predicts a lower PSNR (slope %s)" % p["fit"]["slope"])
u0 = json.load(open(t + "/u0/report.json"))["summary"]["planner"]
expect(u0["uncertainty"] == "none" and u0["uncertainty_db"] == 0 and u0["target_source"] == "given" and u0["target_psnr"] == 30,
       "--plan-uncertainty 0 and a given target recorded")
plain = json.load(open(t + "/plain/report.json"))["summary"]["planner"]
expect(plain["calibration"] is None and plain["uncertainty"] == "none" and plain["uncertainty_db"] == 0, "no calibration: null, uncertainty 0")
expect(plain["fit"]["intercept"] != p["fit"]["intercept"], "the refit differs from the default fit")
k = s["keyframe_frames"]
expect(k[0] == 0 and k[-1] == 39 and all(2 <= b - a <= 12 for a, b in zip(k, k[1:-1])), "gaps within 2..12")
expect(c["window"] is None and all(float(r["offset"]) == 0 for r in rows), "no window: null, offsets 0")
# --calibration-window 3: the offsets and held-out residuals recomputed from
# calibration.csv (Gaussian of 3 frames, prior 2 samples, weights past 5 widths
# dropped; a sample held out with the rest of its walk's segment).
wp = json.load(open(t + "/win/report.json"))["summary"]["planner"]
wc = wp["calibration"]["window"]
wrows = list(csv.DictReader(open(t + "/win/calibration.csv")))
at = [int(r["frame"]) for r in wrows]
seg = [(r["spacing"], r["k0"]) for r in wrows]  # held out together
wres = [float(r["psnr"]) - float(r["predicted"]) for r in wrows]
def offset(f, skip=None):
    num = den = 0.0
    for g, s_, r in zip(at, seg, wres):
        d = (g - f) / 3.0
        if s_ == skip or d * d > 25: continue
        w = math.exp(-0.5 * d * d); num += w * r; den += w
    return num / (den + 2.0)
expect(wc["frames"] == 3 and wc["prior_samples"] == 2, "window 3 frames, prior 2: %s" % wc)
worst = max(abs(offset(f) - float(r["offset"])) for f, r in zip(at, wrows))
expect(worst < 2e-3, "offset column = the smoothed residuals (worst %.5f dB)" % worst)
held = [r - offset(f, skip=s_) for f, s_, r in zip(at, seg, wres)]
rms = math.sqrt(sum(h * h for h in held) / len(held))
expect(abs(rms - wc["held_out_residual_rms_db"]) < 2e-3, "held-out rms from the CSV %.4f = report %.4f" % (rms, wc["held_out_residual_rms_db"]))
expect(wp["uncertainty_db"] == wc["held_out_residual_rms_db"], "the error model is what the window leaves")
offs = [float(r["offset"]) for r in wrows]
expect(wc["offset_min_db"] <= min(offs) + 1e-3 and wc["offset_max_db"] >= max(offs) - 1e-3 and max(offs) > min(offs),
       "the offsets' range over the path holds the sampled frames' (%s)" % wc)
expect(wp["fit"] == p["fit"], "the window leaves the fit alone")
for b in bad: print("FAIL", b)
sys.exit(1 if bad else 0)
PY
rc=$?; check "report, CSV and fixed walk agree" test $rc -eq 0
finish
