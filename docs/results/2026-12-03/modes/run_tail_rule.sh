#!/bin/bash
# The default preset (auto) after the tail rule, first 120 frames of six paths.
cd "$(dirname "$0")/../../../.."; export LP_NUM_THREADS=2
for c in "q3:aggressor|paths/aggressor.json" "q3:delta|paths/delta.json" "outdoor:100k|" "q3:oa_dm5|paths/oa_dm5.json" "indoor:1M|" "torcs:forza|paths/forza.json"; do
  sc=${c%%|*}; p=${c#*|}; pa=""; [ -n "$p" ] && pa="--path $p"
  n=$(echo $sc | tr ':/' '__')
  build/bin/hybridwalk walk --scene $sc $pa --frames 120 --strips 0 --quiet --out /tmp/m/$n >/dev/null 2>&1
  echo $n >> /tmp/m/done
done
echo ALL >> /tmp/m/done
