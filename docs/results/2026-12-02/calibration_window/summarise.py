#!/usr/bin/env python3
"""One row per walk: python3 summarise.py DIR... > walks.csv (each DIR holds walk output dirs)."""
import csv, glob, json, os, sys
w = csv.writer(sys.stdout)
w.writerow(["run", "keyframes", "psnr_median", "psnr_p5", "ssim_median", "predictor", "probe_size",
            "uncertainty", "window_frames", "target_psnr", "median_minus_target", "predicted_psnr_median",
            "residual_sd_db", "held_out_rms_db", "spearman", "calibration_ms", "plan_ms"])
rows = {}
for d in sys.argv[1:]:
    for r in sorted(glob.glob(d + "/*/report.json")):
        s = json.load(open(r))["summary"]
        p = s.get("planner") or {}
        c = p.get("calibration") or {}
        win = c.get("window") or {}
        f = lambda v, n=3: "" if v is None else round(v, n)
        name = os.path.basename(os.path.dirname(r))
        rows[name] = [name, s["keyframes"], f(s["psnr"]["median"]), f(s["psnr"]["p5"]),
                      f(s["ssim"]["median"], 4), p.get("predictor", "fixed"), p.get("probe_size", ""),
                      p.get("uncertainty", ""), win.get("frames", 0) if p else "", f(p.get("target_psnr")),
                      f(s["psnr"]["median"] - p["target_psnr"]) if p else "",
                      f(p.get("predicted_psnr_median")), f(c.get("residual_std_db")),
                      f(win.get("held_out_residual_rms_db")), f(c.get("spearman")), f(c.get("ms"), 0),
                      f(p.get("plan_ms"), 0)]
for name in sorted(rows):
    w.writerow(rows[name])
