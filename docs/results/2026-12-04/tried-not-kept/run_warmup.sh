#!/bin/bash
# The warm-up geometry sample: the second render of the first camera (before,
# /tmp/hw_old) against the faster of its second and third (after,
# build/bin/hybridwalk); default preset, ten paths, two passes, back to back
# per path. Usage: run_warmup.sh [OUT]; then python3 table_warmup.py OUT > table_warmup.md.
cd "$(dirname "$0")/../../../.."; export LP_NUM_THREADS=2; out=${1:-/tmp/wg}
for pass in 1 2; do
for c in "indoor|" "indoor:1M|" "outdoor:100k|" "q3:oa_dm5|paths/oa_dm5.json" "q3:aggressor|paths/aggressor.json" "q3:delta|paths/delta.json" "torcs:forza|paths/forza.json" "torcs:e-track-2|paths/e-track-2.json" "morse:land-1/trees|paths/trees.json" "q3:ps37ctf|paths/ps37ctf.json"; do
  sc=${c%%|*}; p=${c#*|}; pa=""; [ -n "$p" ] && pa="--path $p"
  n=$(echo $sc | tr ':/' '__')
  for b in old new; do
    bin=build/bin/hybridwalk; [ $b = old ] && bin=/tmp/hw_old
    $bin walk --scene $sc $pa --frames 120 --strips 0 --quiet --out $out/${n}_${b}_$pass >/dev/null 2>&1 || echo fail $n $b
  done
done; done
