#!/usr/bin/env python3
"""One row per walk: python3 summarise.py DIR... > walks.csv (each DIR holds walk output dirs)."""
import csv, glob, json, os, sys
w = csv.writer(sys.stdout)
w.writerow(["run", "keyframes", "psnr_median", "psnr_p5", "ssim_median", "predictor", "uncertainty",
            "target_psnr", "predicted_psnr_median", "residual_sd_db", "spearman", "calibration_ms", "plan_ms"])
rows = {}  # run name -> row; a later DIR's run of the same name replaces an earlier one
for d in sys.argv[1:]:
    for r in sorted(glob.glob(d + "/*/report.json")):
        s = json.load(open(r))["summary"]
        p = s.get("planner") or {}
        c = p.get("calibration") or {}
        f = lambda v, n=3: "" if v is None else round(v, n)
        name = os.path.basename(os.path.dirname(r))
        if p and "uncertainty" not in p:  # written before the key existed: a normal sd or none
            p["uncertainty"] = "normal" if p.get("uncertainty_db", 0) > 0 else "none"
            if p["uncertainty"] == "normal":
                name += "_normal"
        rows[name] = [name, s["keyframes"], f(s["psnr"]["median"]),
                    f(s["psnr"]["p5"]), f(s["ssim"]["median"], 4), p.get("predictor", "fixed-10"),
                    p.get("uncertainty", ""), f(p.get("target_psnr")), f(p.get("predicted_psnr_median")),
                    f(c.get("residual_std_db")), f(c.get("spearman")), f(c.get("ms"), 0), f(p.get("plan_ms"), 0)]
for name in sorted(rows):
    w.writerow(rows[name])
