#!/bin/bash
# Each scene: the walk (--mode hybrid, first 120 frames, default preset otherwise) without and with --render-holes.
# Table: python3 table.py ${OUT:-/tmp/render-holes}
cd "$(dirname "$0")/../../../.."; export LP_NUM_THREADS=2
mkdir -p ${OUT:-/tmp/render-holes}
for c in "q3:oa_dm5|paths/oa_dm5.json" "indoor:100k|" "torcs:forza|paths/forza.json" "q3:aggressor|paths/aggressor.json" "torcs:e-track-2|paths/e-track-2.json" "morse:land-1/trees|paths/trees.json" "outdoor:100k|" "indoor:1M|"; do
  sc=${c%%|*}; p=${c#*|}; pa=""; [ -n "$p" ] && pa="--path $p"
  n=$(echo $sc | tr ':/' '__')
  W="build/bin/hybridwalk walk --scene $sc $pa --mode hybrid --frames 120 --strips 0 --quiet"
  $W --out ${OUT:-/tmp/render-holes}/${n}_base >/dev/null 2>&1
  $W --render-holes --out ${OUT:-/tmp/render-holes}/${n}_holes >/dev/null 2>&1
  echo $n >> ${OUT:-/tmp/render-holes}/done
done
echo ALL >> ${OUT:-/tmp/render-holes}/done
