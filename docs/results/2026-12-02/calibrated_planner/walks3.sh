#!/bin/bash
cd /work/main
export LP_NUM_THREADS=2
H=/work/meas/s6/hw3
O=/work/meas/s6/w3; mkdir -p $O
common="--planarity region-local --merge-strips --tau 2^11 --strips 0 --quiet"
sc() { case $1 in oa) echo "--scene q3:oa_dm5 --path paths/oa_dm5.json";; in) echo "--scene indoor";; fz) echo "--scene torcs:forza --path paths/forza.json";; esac; }
w() { name=$1; s=$2; shift 2
  [ -f $O/$name/report.json ] && return
  /usr/bin/time -f "%e s" $H walk $(sc $s) $common --out $O/$name "$@" > $O/$name.log 2>&1
}
ad="--schedule adaptive --plan-by walk-median --min-gap 2 --max-gap 20 --predictor probe-psnr+distance"
for s in oa fz in; do
  w ${s}_cal20_ppd_emp $s $ad --calibrate-spacing 20 --target-psnr fixed:10 --plan-uncertainty empirical
  w ${s}_cal20_ppd_u0 $s $ad --calibrate-spacing 20 --target-psnr fixed:10 --plan-uncertainty 0
done
echo done > $O/done3
