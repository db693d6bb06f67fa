#!/usr/bin/env bash
# Attempt 4: two builds (BASE, and CAL3 with three timed calibration draws
# each) walked RUNS times each at the defaults, interleaved; one JSON line per
# walk (../cpu-warper/summarise.py), then the table (exact-mode agreement of
# every pair of runs, worst / mean).
# Usage: calibration3.sh BASE_BIN CAL3_BIN OUT [RUNS]   (LP_NUM_THREADS=2 as in the study)
set -u
base=$1; cal=$2; out=$3; runs=${4:-3}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../../../.." && pwd)
sum="$here/docs/results/2026-12-06/cpu-warper/summarise.py"
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}
for s in indoor "q3:oa_dm5 --path $here/paths/oa_dm5.json" "q3:ps37ctf --path $here/paths/ps37ctf.json" \
         q3:delta indoor:1M; do
  for r in $(seq 1 "$runs"); do
    for b in base cal3; do
      bin=$base; [ "$b" = cal3 ] && bin=$cal
      d="$out/$(echo "${s%% *}" | tr ':/' '__')/$b-$r"; rm -rf "$d"; mkdir -p "$d" || exit 1
      # shellcheck disable=SC2086
      "$bin" walk --scene $s --quiet --out "$d" >"$d.out" 2>&1 || { echo "failed: $d" >&2; continue; }
      python3 "$sum" "${s%% *}" auto "$b" "$r" "$d/report.json"
    done
  done
done | tee "$out/runs.jsonl"
python3 - "$out/runs.jsonl" <<'PY'
import itertools, json, statistics as st, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.startswith("{")]
agree = lambda a, b: sum(x == y for x, y in zip(a, b)) / len(a)
print("| scene | build | agreement worst / mean | warped frames per run | f/g median (max) | f/g p95 (max) |")
print("| --- | --- | --- | --- | --- | --- |")
for sc in dict.fromkeys(x["scene"] for x in rows):
    for b in ("base", "cal3"):
        xs = [x for x in rows if x["scene"] == sc and x["warper"] == b]
        ags = [agree(p["modes"], q["modes"]) for p, q in itertools.combinations(xs, 2)]
        if not ags:
            continue
        print(f"| {sc} | {b} | {min(ags):.2f} / {st.mean(ags):.2f} | "
              f"{', '.join(str(x['warped_frames']) for x in xs)} | "
              f"{max(x['frame_over_geometry_median'] for x in xs):.3f} | "
              f"{max(x['frame_over_geometry_p95'] for x in xs):.3f} |")
PY
