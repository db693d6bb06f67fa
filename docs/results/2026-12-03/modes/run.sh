#!/bin/bash
cd /work/main
export LP_NUM_THREADS=2
for c in "indoor:100k|" "indoor:1M|" "outdoor:100k|" "q3:oa_dm5|paths/oa_dm5.json" "torcs:forza|paths/forza.json" "q3:delta|paths/delta.json" "q3:aggressor|paths/aggressor.json" "outdoor:1M|" "morse:land-1/trees|paths/trees.json" "torcs:e-track-2|paths/e-track-2.json"; do
  sc=${c%%|*}; p=${c#*|}; pa=""; [ -n "$p" ] && pa="--path $p"
  for preset in default paper; do
    o=/tmp/bt/$(echo $sc | tr ':/' '__')_$preset
    nice -n 5 build/bin/hybridwalk walk --scene $sc $pa --preset $preset --frames 120 --strips 0 --out $o --quiet > $o.stdout 2>&1
    echo "$sc $preset rc=$?" >> /tmp/bt/done.txt
  done
done
echo ALL >> /tmp/bt/done.txt
