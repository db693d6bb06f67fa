#!/bin/bash
# Paper preset against the default preset warping every frame (--mode hybrid),
# holes on at budget 0.3 and off; 120 frames, the three back to back per path.
cd "$(dirname "$0")/../../../.."; export LP_NUM_THREADS=2
out=${1:-/tmp/rhp}; mkdir -p $out
for c in "indoor|" "q3:oa_dm5|paths/oa_dm5.json" "torcs:forza|paths/forza.json"; do
  sc=${c%%|*}; p=${c#*|}; pa=""; [ -n "$p" ] && pa="--path $p"
  n=$(echo $sc | tr ':/' '__')
  build/bin/hybridwalk walk --preset paper --scene $sc $pa --frames 120 --strips 0 --quiet --out $out/${n}_paper >/dev/null 2>&1
  build/bin/hybridwalk walk --scene $sc $pa --frames 120 --mode hybrid --no-render-holes --strips 0 --quiet --out $out/${n}_hybrid_off >/dev/null 2>&1
  build/bin/hybridwalk walk --scene $sc $pa --frames 120 --mode hybrid --render-holes --render-holes-budget 0.3 --strips 0 --quiet --out $out/${n}_hybrid_b0.3 >/dev/null 2>&1
  echo $n >> $out/done
done
echo ALL >> $out/done
