#!/usr/bin/env python3
"""Table (results.csv, README numbers) and plot (stages.png) of the
gpu_frames_bench runs in this folder."""
import csv, glob, json, os, sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

here = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
runs = [json.load(open(f)) for f in sorted(glob.glob(os.path.join(here, "*.json")))]
stages = ["pair_ms", "readback_ms", "compose_ms", "holes_ms", "show_ms"]
with open(os.path.join(here, "results.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["scene", "frames", "variant"] + stages + ["total_ms", "gpu_over_cpu"])
    for r in runs:
        cpu, gpu = r["variants"]
        for v in (cpu, gpu):
            w.writerow([r["scene"], r["frames"], v["variant"]] + ["%.3f" % v[s] for s in stages] +
                       ["%.3f" % v["total_ms"], "%.3f" % (gpu["total_ms"] / cpu["total_ms"])])
for r in runs:
    cpu, gpu = r["variants"]
    print("%-20s cpu %6.2f ms  gpu %6.2f ms  gpu/cpu %.2f  (compose %.2f+%.2f readback vs %.2f+%.2f)" %
          (r["scene"], cpu["total_ms"], gpu["total_ms"], gpu["total_ms"] / cpu["total_ms"],
           cpu["compose_ms"], cpu["readback_ms"], gpu["compose_ms"], gpu["readback_ms"]))

fig, ax = plt.subplots(figsize=(10, 4.5))
labels = ["pair drawn", "readback (CPU: image; GPU: masks)", "composition", "hole pass",
          "shown (CPU: upload)"]
colours = ["#4c72b0", "#dd8452", "#55a868", "#c44e52", "#8172b2"]
x = 0
ticks, names = [], []
for r in runs:
    for k, v in enumerate(r["variants"]):
        bottom = 0
        for s, lab, c in zip(stages, labels, colours):
            ax.bar(x, v[s], bottom=bottom, color=c, label=lab if x == 0 else None, width=0.8)
            bottom += v[s]
        ticks.append(x)
        short = r["scene"] if r["scene"].startswith("indoor") else r["scene"].split(":")[-1].split("/")[-1]
        names.append(("CPU" if k == 0 else "GPU") + "\n" + short)
        x += 1
    x += 0.6
ax.set_xticks(ticks)
ax.set_xticklabels(names, fontsize=7)
ax.set_ylabel("median ms per in-between frame")
m = runs[0]["machine"] if runs else {}
ax.set_title("In-between frame with OpenGL's warper, composed on the CPU or kept on the GPU\n"
             "%s, %s, 512x512, hole pass on" % (m.get("gl_renderer", "?"), m.get("cpu", "?")), fontsize=9)
ax.legend(fontsize=7, loc="upper left")
fig.tight_layout()
fig.savefig(os.path.join(here, "stages.png"), dpi=110)
