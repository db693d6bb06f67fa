#!/bin/bash
# 512² walks: fixed every 10 vs calibrated walk-median at the fixed-10 median.
cd /work/main
export LP_NUM_THREADS=2
H=/work/meas/s6/hw
O=/work/meas/s6/w
mkdir -p $O
common="--planarity region-local --merge-strips --tau 2^11 --strips 0 --quiet"
sc() { case $1 in oa) echo "--scene q3:oa_dm5 --path paths/oa_dm5.json";; in) echo "--scene indoor";; fz) echo "--scene torcs:forza --path paths/forza.json";; esac; }
w() { name=$1; s=$2; shift 2
  [ -f $O/$name/report.json ] && return
  /usr/bin/time -f "%e s" $H walk $(sc $s) $common --out $O/$name "$@" > $O/$name.log 2>&1
}
for s in oa in fz; do
  w ${s}_fixed10 $s
  w ${s}_cal20_ppd $s --schedule adaptive --plan-by walk-median --min-gap 2 --max-gap 20 --predictor probe-psnr+distance --calibrate-spacing 20 --target-psnr fixed:10
  w ${s}_cal20_ppd_u0 $s --schedule adaptive --plan-by walk-median --min-gap 2 --max-gap 20 --predictor probe-psnr+distance --calibrate-spacing 20 --target-psnr fixed:10 --plan-uncertainty 0
done
echo done > $O/done
