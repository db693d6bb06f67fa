#!/usr/bin/env bash
# The main job: install what is missing, build release, and run a headless
# hybrid walkthrough of the built-in indoor scene. Extra args go to
# `hybridwalk walk` (e.g. --scene outdoor --tau 2^15 --save-frames).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh release
build/bin/hybridwalk walk --scene indoor --out out/walk "$@"
echo "open out/walk/report.json and out/walk/strip_*.png (reference | hybrid | difference x4 | holes)"
