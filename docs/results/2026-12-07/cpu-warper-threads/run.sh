#!/bin/bash
# The CPU warper on one or two threads (--warper-threads), and optionally the
# build before this session's warper changes, walking each scene's default
# path at 512² in --mode hybrid and --mode auto, variants interleaved.
# Usage: run.sh NEW_BIN OUT [ROUNDS=2] [OLD_BIN]
#   OLD_BIN: a build of 2859a81 (no --warper-threads: one thread).
# Then: /usr/bin/python3 summarise.py OUT   (writes results.csv, results.json, layers.png here)
set -euo pipefail
new=$1; out=$2; rounds=${3:-2}; old=${4:-}
mkdir -p "$out"
scenes=(indoor indoor:1M q3:oa_dm5 q3:ps37ctf morse:tum_kitchen/tum_kitchen outdoor torcs:forza)
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../../../.." && pwd)
for round in $(seq "$rounds"); do
  for sc in "${scenes[@]}"; do
    extra=()
    case $sc in
      q3:oa_dm5) extra=(--path "$repo/paths/oa_dm5.json") ;;
      q3:ps37ctf) extra=(--path "$repo/paths/ps37ctf.json") ;;
      torcs:forza) extra=(--path "$repo/paths/forza.json") ;;
    esac
    for mode in hybrid auto; do
      for v in old t1 t2; do
        name=$(echo "$sc" | tr ':/' '__')-$mode-$v-r$round
        case $v in
          old) [ -n "$old" ] || continue; cmd=("$old" walk) ;;
          t1) cmd=("$new" walk --warper-threads 1) ;;
          t2) cmd=("$new" walk --warper-threads 2) ;;
        esac
        echo "$name" >&2
        "${cmd[@]}" --scene "$sc" "${extra[@]}" --mode "$mode" --out "$out/$name" --quiet >/dev/null
      done
    done
  done
done
