#!/bin/bash
# usage: run.sh TAG  — async walks with and without the automatic budget
H=/work/main/build/bin/hybridwalk
cd /work/main
tag=$1
for sc in indoor outdoor q3:oa_dm5 torcs:forza; do
  path=""
  case $sc in q3:oa_dm5) path="--path paths/oa_dm5.json";; torcs:forza) path="--path paths/forza.json";; esac
  name=${sc#*:}
  for lod in def rlms; do
    lo=""; [ $lod = rlms ] && lo="--planarity region-local --merge-strips"
    for b in off auto auto75; do
      bo="--pixel-age"; [ $b = auto ] && bo="--frame-budget-ms auto"; [ $b = auto75 ] && bo="--frame-budget-ms auto --frame-budget-quantile 0.75"
      echo "$(date +%T) $tag $name $lod $b load $(cut -d' ' -f1 /proc/loadavg)"
      $H walk --scene $sc $path $lo --async-keyframes --strips 0 --quiet $bo --out /work/meas/s5/bud/$tag/${name}_${lod}_$b >/dev/null 2>/work/meas/s5/bud/$tag.${name}_${lod}_$b.err || echo FAILED
    done
  done
done
echo done
