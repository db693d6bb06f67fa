#!/bin/bash
# The new default preset (holes drawn, budget 0.25), the same without holes,
# and the paper preset; first 120 frames of nine paths, back to back per path.
cd "$(dirname "$0")/../../../.."; export LP_NUM_THREADS=2
out=${1:-/tmp/rhf}; mkdir -p $out
for c in "indoor|" "indoor:1M|" "outdoor:100k|" "q3:oa_dm5|paths/oa_dm5.json" "q3:aggressor|paths/aggressor.json" "q3:delta|paths/delta.json" "torcs:forza|paths/forza.json" "torcs:e-track-2|paths/e-track-2.json" "morse:land-1/trees|paths/trees.json"; do
  sc=${c%%|*}; p=${c#*|}; pa=""; [ -n "$p" ] && pa="--path $p"
  n=$(echo $sc | tr ':/' '__')
  build/bin/hybridwalk walk --scene $sc $pa --frames 120 --strips 2 --quiet --out $out/${n}_default >/dev/null 2>&1
  build/bin/hybridwalk walk --scene $sc $pa --frames 120 --no-render-holes --strips 0 --quiet --out $out/${n}_noholes >/dev/null 2>&1
  build/bin/hybridwalk walk --preset paper --scene $sc $pa --frames 120 --strips 0 --quiet --out $out/${n}_paper >/dev/null 2>&1
  echo $n >> $out/done
done
echo ALL >> $out/done
