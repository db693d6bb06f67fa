#!/bin/bash
# The in-between frame's cost against the geometry frame, default (holes
# drawn, and without them) against the paper, every frame warped.
# Usage: run.sh [OUT]; then python3 in_between.py OUT/* and stages.py OUT/*.
cd "$(dirname "$0")/../../../.."; export LP_NUM_THREADS=2; out=${1:-/tmp/gf}
for s in indoor indoor:1M q3:oa_dm5 torcs:forza; do
  n=$(echo $s | tr ':/' '__'); p=""
  [ $s = q3:oa_dm5 ] && p="--path paths/oa_dm5.json"; [ $s = torcs:forza ] && p="--path paths/forza.json"
  for v in "default-holes:--mode hybrid" "default-noholes:--mode hybrid --no-render-holes" \
           "paper:--preset paper" "auto:"; do
    t=${v%%:*}; o=${v#*:}
    build/bin/hybridwalk walk --scene $s $p $o --frames 120 --strips 0 --quiet --out $out/${n}-$t >/dev/null 2>&1 || echo fail $n $t
  done
done
