#!/usr/bin/env bash
# Gradient-following LOD tolerance (LodOptions::tauGradient):
# region-local + merge, 512x512, 61 frames, tau in {2^3, 2^5, 2^7, 2^11},
# tauGradient A in {0, S, 4S} (S = the suggested value). Run from the repo root:
#   bash docs/results/2026-12-01/gradtol/run.sh build/bin/hybridwalk S OUTDIR
set -eu
hw=$1; s=$2; out=$3
mkdir -p "$out"
a4=$(python3 -c "print($s*4)")
for sc in "q3:oa_dm5 paths/oa_dm5.json oa_dm5" "torcs:forza paths/forza.json forza"; do
  set -- $sc
  for tau in 2^3 2^5 2^7 2^11; do
    for a in 0 "$s" "$a4"; do
      d="$out/$3_tau${tau/^/e}_A$a"
      [ -f "$d/report.json" ] && continue
      "$hw" walk --scene "$1" --path "$2" --frames 61 --strips 0 --planarity region-local \
        --merge-strips --tau "$tau" --tau-gradient "$a" --out "$d" --quiet >/dev/null
    done
  done
done
