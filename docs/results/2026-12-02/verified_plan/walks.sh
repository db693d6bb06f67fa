#!/bin/bash
# The 512² walks of this folder: probe-psnr+features calibrated on the scene
# (every 20 and 10 frames), target fixed-10's measured median, empirical error
# model, 64-px probes, calibration window 3 frames, and the verified planner
# (--verify-rounds 40) with --verify-optimism 0.5 or 1 dB.
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
for s in out in oa fz; do
  for o in 1 0.5; do
    w ${s}_verify_o$o $s $ad --probe-size 64 --calibration-window 3 --verify-rounds 40 --verify-optimism $o
  done
done
# The same plan without the rounds (the predictor's own schedule).
for s in out in oa fz; do
  w ${s}_plan $s $ad --probe-size 64 --calibration-window 3
done
