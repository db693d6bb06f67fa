#!/usr/bin/env bash
# In-between frames with OpenGL's warper, composed on the CPU and kept on the
# GPU, each frame drawn both ways in turn (bench/gpu_frames_bench.cpp), on
# seven scenes at 512x512, 60 frames of each default path (keyframes every 10).
# Usage: docs/results/2026-12-07/frames-on-gpu/run.sh [BUILD_DIR]
set -eu
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build}
for scene in indoor indoor:1M q3:oa_dm5 q3:ps37ctf morse:tum_kitchen/tum_kitchen outdoor torcs:forza; do
  tag=$(echo "$scene" | tr ':/' '__')
  LP_NUM_THREADS=2 "$build/bin/gpu_frames_bench" "$scene" 512 61 "$here/$tag.json"
done
/usr/bin/python3 "$here/summarise.py" "$here"
