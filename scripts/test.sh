#!/usr/bin/env bash
# Install what is missing, build release with warnings as errors, and run the
# whole test suite (CPU, GL on OSMesa, command-line) through CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh release -DHW_WERROR=ON
cd build
# llvmpipe threads: 2 gave the steadiest figures here (NOTES-GL.md).
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}
# Under Xvfb, so the windowed (GLFW) tests run for real; headless tests use OSMesa.
xvfb-run -a -s "-screen 0 1280x1024x24" ctest --output-on-failure -j 2 --timeout 600
