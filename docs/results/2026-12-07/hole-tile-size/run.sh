#!/bin/bash
# The hole pass's tile size: every scene's walk (512², the defaults,
# --mode hybrid, so that every setting draws the same frames but for the hole
# pass) with --hole-tile-px 8, 16 (the default) and 32; the settings in turn,
# per scene.
# Usage: run.sh BIN OUT
# Then: /usr/bin/python3 summarise.py OUT   (writes results.csv and tiles.png here)
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
  for tile in 8 16 32; do
    name=$(echo "$sc" | tr ':/' '__')-$tile
    echo "$name" >&2
    "$bin" walk --scene "$sc" "${extra[@]}" --mode hybrid --hole-tile-px "$tile" \
      --out "$out/$name" --quiet >/dev/null
  done
done
