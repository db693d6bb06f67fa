#!/bin/bash
# The hole pass with and without a cap of 12 rectangles (--hole-rects-max 12,
# the default, against 0 = every rectangle found): every scene's walk (512²,
# the defaults) with --mode hybrid, where both draw the same frames but for
# the hole pass, and with --mode auto --auto-pin off, where the budget caps
# the pass and auto chooses from this run's costs; the two settings in turn,
# per scene.
# Usage: run.sh BIN OUT
# Then: /usr/bin/python3 summarise.py OUT   (writes results.csv and rects.png here)
set -euo pipefail
bin=$1; out=$2
mkdir -p "$out"
scenes=(indoor indoor:1M q3:oa_dm5 q3:ps37ctf morse:tum_kitchen/tum_kitchen outdoor torcs:forza)
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../../../.." && pwd)
export LP_NUM_THREADS=2
for sc in "${scenes[@]}"; do
  extra=()
  case $sc in
    q3:oa_dm5) extra=(--path "$repo/paths/oa_dm5.json") ;;
    q3:ps37ctf) extra=(--path "$repo/paths/ps37ctf.json") ;;
    torcs:forza) extra=(--path "$repo/paths/forza.json") ;;
  esac
  for mode in hybrid auto; do
    for variant in capped uncapped; do
      max=12; [ "$variant" = uncapped ] && max=0
      name=$(echo "$sc" | tr ':/' '__')-$mode-$variant
      echo "$name" >&2
      "$bin" walk --scene "$sc" "${extra[@]}" --mode "$mode" --auto-pin off --hole-rects-max "$max" \
        --out "$out/$name" --quiet >/dev/null
    done
  done
done
