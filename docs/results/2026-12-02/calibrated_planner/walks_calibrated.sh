#!/bin/bash
# The calibrated adaptive walks of README.md: per scene, the empirical error
# model and the plain count, planned for fixed-10's measured median.
# Usage: walks_calibrated.sh HYBRIDWALK PREDICTOR OUT   (run from the repository root)
# PREDICTOR: probe-psnr+distance (ppd, runs in w3) or probe-psnr+features (ppf, w4).
H=$1; P=$2; O=$3
export LP_NUM_THREADS=2
mkdir -p "$O"
tag=$([ "$P" = probe-psnr+features ] && echo ppf || echo ppd)
common="--planarity region-local --merge-strips --tau 2^11 --strips 0 --quiet"
sc() { case $1 in oa) echo "--scene q3:oa_dm5 --path paths/oa_dm5.json";; in) echo "--scene indoor";; fz) echo "--scene torcs:forza --path paths/forza.json";; esac; }
ad="--schedule adaptive --plan-by walk-median --min-gap 2 --max-gap 20 --predictor $P --calibrate-spacing 20 --target-psnr fixed:10"
for s in oa fz in; do
  for u in empirical 0; do
    name=${s}_cal20_${tag}_$([ $u = 0 ] && echo u0 || echo emp)
    [ -f "$O/$name/report.json" ] && continue
    /usr/bin/time -f "%e s" "$H" walk $(sc $s) $common $ad --plan-uncertainty $u --out "$O/$name" > "$O/$name.log" 2>&1
  done
done
