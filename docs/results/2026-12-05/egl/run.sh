#!/usr/bin/env bash
# EGL-llvmpipe against OSMesa-llvmpipe on the same walk: ROUNDS interleaved
# pairs of indoor walks of FRAMES frames (--gl egl, then --gl osmesa, the
# order alternating each round; --mode hybrid so both draw the same frames),
# each report's median frame_ms, in_between_ms and reference_ms; writes
# results.csv and prints the per-round and overall ratios.
# Usage: run.sh HYBRIDWALK OUTDIR [ROUNDS] [FRAMES]
set -euo pipefail
hw=$1; out=$2; rounds=${3:-5}; frames=${4:-0}
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}
mkdir -p "$out"
for i in $(seq 1 "$rounds"); do
  order="egl osmesa"; [ $((i % 2)) = 0 ] && order="osmesa egl"
  for b in $order; do
    "$hw" walk --scene indoor --frames "$frames" --mode hybrid --strips 0 --quiet --gl "$b" \
      --out "$out/$b-$i" >/dev/null 2>&1
  done
done
python3 - "$out" "$rounds" <<'PY'
import csv, json, statistics, sys
out, rounds = sys.argv[1], int(sys.argv[2])
keys = ["frame_ms", "in_between_ms", "reference_ms"]
rows = []
for i in range(1, rounds + 1):
    for b in ("egl", "osmesa"):
        s = json.load(open(f"{out}/{b}-{i}/report.json"))["summary"]
        m = s["machine"]
        rows.append([i, b, m["gl_backend"], m["gl_renderer"]] + [s[k]["median"] for k in keys])
with open(f"{out}/results.csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["round", "gl", "gl_backend", "gl_renderer"] + [k + "_median" for k in keys])
    w.writerows(rows)
print("round  " + "  ".join(f"{k}: egl / osmesa = ratio" for k in keys))
ratios = {k: [] for k in keys}
for i in range(1, rounds + 1):
    e = [r for r in rows if r[0] == i and r[1] == "egl"][0]
    o = [r for r in rows if r[0] == i and r[1] == "osmesa"][0]
    cells = []
    for j, k in enumerate(keys):
        a, b = e[4 + j], o[4 + j]
        ratios[k].append(a / b)
        cells.append(f"{a:.2f} / {b:.2f} = {a / b:.3f}")
    print(f"{i:5d}  " + "  ".join(cells))
for k in keys:
    egl = statistics.median(r[4 + keys.index(k)] for r in rows if r[1] == "egl")
    osm = statistics.median(r[4 + keys.index(k)] for r in rows if r[1] == "osmesa")
    print(f"{k}: median over rounds egl {egl:.2f} ms, osmesa {osm:.2f} ms; per-round ratio median "
          f"{statistics.median(ratios[k]):.3f}, range {min(ratios[k]):.3f}..{max(ratios[k]):.3f}, "
          f"egl faster in {sum(1 for x in ratios[k] if x < 1)} of {rounds}")
PY
