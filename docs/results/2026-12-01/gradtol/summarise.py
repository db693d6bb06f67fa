# Collects the walk reports written by run.sh into gradtol.csv (stdout too).
import json, pathlib, sys
out = pathlib.Path(sys.argv[1])
rows = ["scene,tau,tau_gradient,keyframes,quads_per_keyframe_median,one_pixel_leaves_median,"
        "psnr_median,psnr_p5,in_between_ms_median,lod_build_ms_median,delta_ms_median"]
for rep in sorted(out.glob("*/report.json")):
    r = json.load(open(rep))
    s = r["summary"]
    d = sorted(f["ms"]["delta"] for f in r["frames"] if isinstance(f.get("ms"), dict) and "delta" in f["ms"])
    dm = d[len(d) // 2] if d else float("nan")
    rows.append(",".join(str(v) for v in [
        s["scene"]["name"], s["tau"], s["tau_gradient"], s["keyframes"],
        s["quads_per_keyframe"]["median"], s["one_pixel_leaves_per_keyframe"]["median"],
        round(s["psnr"]["median"], 2), round(s["psnr"]["p5"], 2),
        round(s["in_between_ms"]["median"], 2), round(s["lod_build_ms"]["median"], 3), round(dm, 3)]))
print("\n".join(rows))
