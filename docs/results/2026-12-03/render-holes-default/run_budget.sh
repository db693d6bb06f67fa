#!/bin/bash
# Default preset (auto): holes off, and on with budgets 0.15, 0.3 and no cap
# (0), first 120 frames of nine paths, the four back to back per path.
cd "$(dirname "$0")/../../../.."; export LP_NUM_THREADS=2
out=${1:-/tmp/rhb}; mkdir -p $out
for c in "indoor|" "indoor:1M|" "outdoor:100k|" "q3:oa_dm5|paths/oa_dm5.json" "q3:aggressor|paths/aggressor.json" "q3:delta|paths/delta.json" "torcs:forza|paths/forza.json" "torcs:e-track-2|paths/e-track-2.json" "morse:land-1/trees|paths/trees.json"; do
  sc=${c%%|*}; p=${c#*|}; pa=""; [ -n "$p" ] && pa="--path $p"
  n=$(echo $sc | tr ':/' '__')
  build/bin/hybridwalk walk --scene $sc $pa --frames 120 --no-render-holes --strips 0 --quiet --out $out/${n}_off >/dev/null 2>&1
  for b in 0.15 0.3 0; do
    build/bin/hybridwalk walk --scene $sc $pa --frames 120 --render-holes --render-holes-budget $b --strips 0 --quiet --out $out/${n}_b$b >/dev/null 2>&1
  done
  echo $n >> $out/done
done
echo ALL >> $out/done
