#!/usr/bin/env bash
# Configure and build a preset (default: release). Extra args go to cmake.
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${1:-release}
shift || true
jobs=$(nproc 2>/dev/null || echo 2)
cmake --preset "$preset" "$@" >/dev/null
cmake --build --preset "$preset" -j "$jobs"
