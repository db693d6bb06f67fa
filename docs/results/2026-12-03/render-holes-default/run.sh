#!/bin/bash
# --render-holes off and on, default preset (auto) and --mode hybrid, first 120
# frames of nine paths; each pair back to back so the machine load is alike.
cd "$(dirname "$0")/../../../.."; export LP_NUM_THREADS=2
out=${1:-/tmp/rhd}; mkdir -p $out
for c in "indoor|" "indoor:1M|" "outdoor:100k|" "q3:oa_dm5|paths/oa_dm5.json" "q3:aggressor|paths/aggressor.json" "q3:delta|paths/delta.json" "torcs:forza|paths/forza.json" "torcs:e-track-2|paths/e-track-2.json" "morse:land-1/trees|paths/trees.json"; do
  sc=${c%%|*}; p=${c#*|}; pa=""; [ -n "$p" ] && pa="--path $p"
  n=$(echo $sc | tr ':/' '__')
  for mode in auto hybrid; do
    for rh in no-render-holes render-holes; do
      build/bin/hybridwalk walk --scene $sc $pa --frames 120 --mode $mode --$rh --strips 0 --quiet --out $out/${n}_${mode}_${rh} >/dev/null 2>$out/${n}_${mode}_${rh}.err
    done
  done
  echo $n >> $out/done
done
echo ALL >> $out/done
