#!/usr/bin/env bash
# Walks each scene with the layers drawn by OpenGL (--warper gl) and by the
# CPU warper (--warper cpu), the two interleaved, ROUNDS times; --mode hybrid
# (every in-between frame warped) and then --mode auto (the default), and
# prints one summary per walk (summarise.py) as JSON lines.
# Usage: run.sh HYBRIDWALK OUT [ROUNDS]   (LP_NUM_THREADS=2 as in the study)
set -u
hw=$1; out=$2; rounds=${3:-2}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../../../.." && pwd)
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}
scenes=(
  "indoor"
  "outdoor"
  "indoor:1M"
  "q3:oa_dm5 --path $here/paths/oa_dm5.json"
  "q3:ps37ctf --path $here/paths/ps37ctf.json"
  "q3:delta"
)
for mode in hybrid auto; do
  for s in "${scenes[@]}"; do
    name=$(echo "${s%% *}" | tr ':/' '__')
    for r in $(seq 1 "$rounds"); do
      for w in gl cpu; do
        d="$out/$mode/$name/$w$r"; rm -rf "$d"; mkdir -p "$d" || exit 1
        # shellcheck disable=SC2086
        "$hw" walk --scene $s --mode $mode --warper $w --quiet --out "$d" >"$d.out" 2>&1 ||
          { echo "run.sh: $s --warper $w failed (see $d.out)" >&2; continue; }
        python3 "$(dirname "${BASH_SOURCE[0]}")/summarise.py" "${s%% *}" "$mode" "$w" "$r" "$d/report.json"
      done
    done
  done
done
