#!/usr/bin/env bash
# Walks each scene PAIRS times back to back with `--mode auto` (the default)
# and prints scripts/auto_agreement.py for each pair as one JSON line.
# Usage: run.sh HYBRIDWALK OUT [PAIRS [SCENE...]]   (LP_NUM_THREADS=2 as in the study;
#        SCENE: only the listed scenes, by name, e.g. indoor q3:oa_dm5)
set -u
hw=$1; out=$2; pairs=${3:-3}; shift 3 2>/dev/null || shift $#; only=" $* "
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../../../.." && pwd)
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}
scenes=(
  "indoor"
  "indoor:1M"
  "q3:oa_dm5 --path $here/paths/oa_dm5.json"
  "outdoor"
  "torcs:forza --path $here/paths/forza.json"
  "morse:tum_kitchen/tum_kitchen"
  "q3:ps37ctf --path $here/paths/ps37ctf.json"
)
for s in "${scenes[@]}"; do
  [ "$only" = "  " ] || [[ "$only" == *" ${s%% *} "* ]] || continue
  name=$(echo "${s%% *}" | tr ':/' '__')
  mkdir -p "$out/$name" || exit 1
  for p in $(seq 1 "$pairs"); do
    for r in a b; do
      d="$out/$name/$p$r"; rm -rf "$d"
      # shellcheck disable=SC2086
      "$hw" walk --scene $s --quiet --out "$d" >"$out/$name/$p$r.out" 2>&1 ||
        { echo "run.sh: $s failed (see $out/$name.$p$r.out)" >&2; continue 2; }
    done
    echo "{\"scene\": \"${s%% *}\", \"pair\": $p, \"agreement\": $(python3 "$here/scripts/auto_agreement.py" --json "$out/$name/${p}a/report.json" "$out/$name/${p}b/report.json")}"
  done
done
