#!/bin/bash
# Hole budget 0.25 / 0.5 / 1 on the three paths that warp, idle machine, two passes
# (the table also has two more passes of indoor and q3:delta at 0.25 and 0.5).
cd "$(dirname "$0")/../../../.."; export LP_NUM_THREADS=2
out=${1:-/tmp/bud/out}; mkdir -p $out
for rep in 1 2; do
for c in "indoor|" "q3:oa_dm5|paths/oa_dm5.json" "indoor:1M|"; do
  sc=${c%%|*}; p=${c#*|}; pa=""; [ -n "$p" ] && pa="--path $p"
  n=$(echo $sc | tr ':/' '__')
  for b in 0.25 0.5 1; do
    build/bin/hybridwalk walk --scene $sc $pa --frames 120 --strips 0 --quiet --render-holes-budget $b --out $out/${n}_b${b}_r$rep >/dev/null 2>&1
  done
done; done
echo ALL > $out/done
