#!/bin/bash
# The 512² walks of this folder: probe-psnr+features calibrated on the scene
# (every 20 and 10 frames), target fixed-10's measured median, empirical error
# model; 64- or 128-px probes, calibration window 0 or 3 frames.
# Usage: walks.sh HYBRIDWALK OUT_DIR   (run from the source tree; paths/ is read)
H=${1:?hybridwalk}; O=${2:?out dir}; mkdir -p "$O"
export LP_NUM_THREADS=2
common="--planarity region-local --merge-strips --tau 2^11 --strips 0 --quiet"
sc() { case $1 in oa) echo "--scene q3:oa_dm5 --path paths/oa_dm5.json";; in) echo "--scene indoor";;
                  fz) echo "--scene torcs:forza --path paths/forza.json";; out) echo "--scene outdoor";; esac; }
w() { name=$1; s=$2; shift 2
  [ -f "$O/$name/report.json" ] && return
  /usr/bin/time -f "%e s" "$H" walk $(sc $s) $common --out "$O/$name" "$@" > "$O/$name.log" 2>&1
}
ad="--schedule adaptive --plan-by walk-median --min-gap 2 --max-gap 20 --predictor probe-psnr+features --calibrate-spacing 20 --target-psnr fixed:10 --plan-uncertainty empirical"
for s in fz oa in out; do
  w ${s}_p64_ppf_emp $s $ad --probe-size 64
  w ${s}_p64_ppf_emp_w3 $s $ad --probe-size 64 --calibration-window 3
  w ${s}_p128_ppf_emp $s $ad --probe-size 128
  w ${s}_p128_ppf_emp_w3 $s $ad --probe-size 128 --calibration-window 3
done
w out_p64_ppd_u0 out --schedule adaptive --plan-by walk-median --min-gap 2 --max-gap 20 --predictor probe-psnr+distance --calibrate-spacing 20 --target-psnr fixed:10 --plan-uncertainty 0
# A third calibration walk, every 15 frames (with fixed:10's every 10 and every 20).
for s in fz oa; do
  w ${s}_p128_ppf_emp_w3_cal15 $s ${ad/--calibrate-spacing 20/--calibrate-spacing 15,20} --probe-size 128 --calibration-window 3
done
