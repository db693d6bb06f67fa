#!/usr/bin/python3
"""Table (README fragment), per-config aggregates and the PSNR-vs-time plot from runs*.csv.

  /usr/bin/python3 summarise.py runs.csv [runs_rep2.csv ...]   # writes table.md, aggregate.md, pareto.png

Several CSVs = repeated runs of the same cells: PSNR/quads are deterministic (taken from the
first), the ms columns are the median over the repeats (the machine is shared: timing noise).
The plot needs matplotlib (Debian python3-matplotlib; /usr/bin/python3).
"""
import csv, math, os, statistics, sys
from collections import OrderedDict, defaultdict

HERE = os.path.dirname(os.path.abspath(__file__))
MS = ["in_between_ms_median", "in_between_ms_p95", "frame_ms_median", "frame_ms_p95",
      "in_between_frame_ms_median", "reference_ms_median", "keyframe_build_ms_median"]

def load(paths):
    cells = OrderedDict()
    for p in paths:
        for r in csv.DictReader(open(p)):
            k = (r["scene"], r["config"])
            if k not in cells:
                cells[k] = dict(r); cells[k]["_ms"] = defaultdict(list)
            for m in MS:
                if r[m] not in ("", "None"):
                    cells[k]["_ms"][m].append(float(r[m]))
    for c in cells.values():
        for m in MS:
            v = c["_ms"][m]
            c[m] = statistics.median(v) if v else None
        c["repeats"] = len(c["_ms"]["in_between_ms_median"])
        for f in ("psnr_median", "psnr_p5", "ssim_median"):
            c[f] = float(c[f]) if c[f] not in ("", "None") else None
        c["quads_median"] = float(c["quads_median"])
    return cells

def f(x, d=2):
    return "" if x is None else f"{x:.{d}f}"

def main():
    paths = sys.argv[1:] or [os.path.join(HERE, "runs.csv")]
    cells = load(paths)
    scenes = list(OrderedDict.fromkeys(s for s, _ in cells))
    configs = list(OrderedDict.fromkeys(c for _, c in cells))
    # --- per-scene table
    out = ["| scene | config | PSNR med | PSNR p5 | SSIM | in-between ms | frame ms med / p95 | reference ms | quads/keyframe | ΔdB vs paper | time ÷ paper | (ib÷ref) ÷ paper's |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    agg = defaultdict(lambda: {"ddb": [], "ratio": [], "nratio": [], "qratio": [], "scenes": 0, "front": 0})
    for s in scenes:
        base = cells.get((s, "paper"))
        pts = [(cells[(s, c)]["in_between_ms_median"], cells[(s, c)]["psnr_median"], c)
               for c in configs if (s, c) in cells]
        for c in configs:
            r = cells.get((s, c))
            if not r:
                continue
            ddb = ratio = nratio = None
            if base and r["psnr_median"] is not None and base["psnr_median"] is not None:
                ddb = r["psnr_median"] - base["psnr_median"]
                ratio = r["in_between_ms_median"] / base["in_between_ms_median"]
                # load-normalised: in-between ms over the same run's geometry (reference) ms
                nratio = (r["in_between_ms_median"] / r["reference_ms_median"]) / (
                    base["in_between_ms_median"] / base["reference_ms_median"])
                qratio = r["quads_median"] / base["quads_median"]
                agg[c]["ddb"].append(ddb); agg[c]["ratio"].append(ratio)
                agg[c]["nratio"].append(nratio); agg[c]["qratio"].append(qratio)
            # Pareto front: no other config both faster and better (by > 0.05 dB)
            ms, db = r["in_between_ms_median"], r["psnr_median"]
            dominated = any(o_ms < ms and o_db > db + 0.05 for o_ms, o_db, oc in pts if oc != c)
            agg[c]["front"] += 0 if dominated else 1
            agg[c]["scenes"] += 1
            out.append(f"| {s} | {c} | {f(r['psnr_median'])} | {f(r['psnr_p5'])} | {f(r['ssim_median'], 3)} | "
                       f"{f(r['in_between_ms_median'], 1)} | {f(r['frame_ms_median'], 1)} / {f(r['frame_ms_p95'], 1)} | "
                       f"{f(r['reference_ms_median'], 1)} | {int(r['quads_median'])} | "
                       f"{'' if ddb is None else f'{ddb:+.2f}'} | {'' if ratio is None else f'{ratio:.2f}'} | "
                       f"{'' if nratio is None else f'{nratio:.2f}'} |")
    open(os.path.join(HERE, "table.md"), "w").write("\n".join(out) + "\n")
    # --- aggregate over scenes
    a = ["| config | scenes | mean ΔdB vs paper | min ΔdB | max ΔdB | geo-mean time ÷ paper | max time ÷ paper | geo-mean (ib÷ref) ÷ paper's | geo-mean quads ÷ paper | on the scene's Pareto front |",
         "|---|---|---|---|---|---|---|---|---|---|"]
    for c in configs:
        g = agg[c]
        if not g["ddb"]:
            continue
        gm = math.exp(statistics.mean(math.log(x) for x in g["ratio"]))
        gn = math.exp(statistics.mean(math.log(x) for x in g["nratio"]))
        gq = math.exp(statistics.mean(math.log(x) for x in g["qratio"]))
        a.append(f"| {c} | {len(g['ddb'])} | {statistics.mean(g['ddb']):+.2f} | {min(g['ddb']):+.2f} | {max(g['ddb']):+.2f} | {gm:.2f} | "
                 f"{max(g['ratio']):.2f} | {gn:.2f} | {gq:.2f} | {g['front']}/{g['scenes']} |")
    # --- in-between vs geometry frame
    REC = os.environ.get("HW_RECOMMENDED", "rl+m px0.125")
    a += ["", f"| scene | triangles | geometry frame ms (reference) | paper: in-between ms | paper: in-between ÷ geometry | {REC}: in-between ms | {REC}: in-between ÷ geometry | {REC}: frame ms median / p95 | in-between cheaper than geometry? |",
          "|---|---|---|---|---|---|---|---|---|"]
    for s in scenes:
        b = cells.get((s, "paper")); r = cells.get((s, REC))
        if b and r:
            rb = b["in_between_ms_median"] / b["reference_ms_median"]
            rr = r["in_between_ms_median"] / r["reference_ms_median"]
            verdict = "yes" if rr < 0.8 else ("no" if rr > 1.2 else "about even")
            a.append(f"| {s} | {b['triangles']} | {f(b['reference_ms_median'], 1)} (rec. run {f(r['reference_ms_median'], 1)}) | "
                     f"{f(b['in_between_ms_median'], 1)} | {rb:.2f} | {f(r['in_between_ms_median'], 1)} | {rr:.2f} | "
                     f"{f(r['frame_ms_median'], 1)} / {f(r['frame_ms_p95'], 1)} | {verdict} |")
    open(os.path.join(HERE, "aggregate.md"), "w").write("\n".join(a) + "\n")
    # --- the recommendation against the paper, per scene
    rc = ["| scene | paper PSNR (dB) | recommended PSNR (dB) | ΔdB | PSNR p5 paper → rec. | in-between ms paper → rec. | time ÷ paper | (ib÷ref) ÷ paper's | quads paper → rec. | best ΔdB elsewhere in the grid |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for s in scenes:
        b = cells.get((s, "paper")); r = cells.get((s, REC))
        if not (b and r):
            continue
        best = max((cells[(s, c)]["psnr_median"], c) for c in configs if (s, c) in cells)
        nr = (r["in_between_ms_median"] / r["reference_ms_median"]) / (b["in_between_ms_median"] / b["reference_ms_median"])
        rc.append(f"| {s} | {f(b['psnr_median'])} | {f(r['psnr_median'])} | {r['psnr_median'] - b['psnr_median']:+.2f} | "
                  f"{f(b['psnr_p5'])} → {f(r['psnr_p5'])} | {f(b['in_between_ms_median'], 1)} → {f(r['in_between_ms_median'], 1)} | "
                  f"{r['in_between_ms_median'] / b['in_between_ms_median']:.2f} | {nr:.2f} | "
                  f"{int(b['quads_median'])} → {int(r['quads_median'])} | {best[0] - b['psnr_median']:+.2f} ({best[1]}) |")
    open(os.path.join(HERE, "recommended.md"), "w").write("\n".join(rc) + "\n")

    sys.stdout.write("\n".join(a) + "\n")
    # --- plot
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("no matplotlib: plot skipped"); return
    n = len(scenes); cols = 4; rows = (n + cols - 1) // cols
    fig, axs = plt.subplots(rows, cols, figsize=(5.2 * cols, 4.4 * rows))
    cmap = plt.get_cmap("tab20")
    colour = {c: cmap(i % 20) for i, c in enumerate(configs)}
    for i, s in enumerate(scenes):
        ax = axs.flat[i]
        for c in configs:
            r = cells.get((s, c))
            if not r or r["psnr_median"] is None:
                continue
            x, y = r["in_between_ms_median"], r["psnr_median"]
            k = configs.index(c)
            ax.scatter([x], [y], color=colour[c], s=70 if c == "paper" else 34,
                       marker="*" if c == "paper" else "osD^v<>ph8"[k % 10],
                       edgecolor="k", linewidth=0.4, zorder=3, label=f"{k}: {c}" if i == 0 else None)
            ax.annotate(str(k), (x, y), fontsize=6, xytext=(3, 2), textcoords="offset points")
        ax.set_title(f"{s} ({cells[(s, configs[0])]['triangles'] if (s, configs[0]) in cells else ''} tris)", fontsize=9)
        ax.set_xlabel("in-between ms (median)", fontsize=8); ax.set_ylabel("PSNR median (dB)", fontsize=8)
        lo, hi = ax.get_ylim()
        if hi - lo < 1.0:  # at least 1 dB tall, so that 0.01 dB steps do not look like cliffs
            m = 0.5 * (lo + hi); ax.set_ylim(m - 0.5, m + 0.5)
        ax.set_xlim(left=0)
        ax.tick_params(labelsize=7); ax.grid(alpha=0.3)
    for j in range(n, rows * cols):
        axs.flat[j].axis("off")
    h, l = axs.flat[0].get_legend_handles_labels()
    axs.flat[rows * cols - 1].legend(h, l, loc="center", fontsize=9, title="configuration (number = label)")
    fig.suptitle("PSNR vs in-between ms per scene (512², LP_NUM_THREADS=2; ★ = paper preset)", fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    fig.savefig(os.path.join(HERE, "pareto.png"), dpi=90)
    print("pareto.png written")

if __name__ == "__main__":
    main()
