#!/usr/bin/env bash
# The paper-LOD cells of torcs:forza, run beside run.sh's other cells to meet the time.
set -u
hw=$1; root=$2; src=$(cd "$(dirname "$0")/../../../.." && pwd)
export LP_NUM_THREADS=2
mkdir -p "$root/forza/paper"
for c in overlay depth-merge blend; do for f in copy reproject; do
  out="$root/forza/paper/$c-$f"; [ -s "$out/report.json" ] && continue
  echo "== forza paper $c $f $(date +%T)"
  $hw walk --scene torcs:forza --path "$src/paths/forza.json" --compose $c --fallback $f --strips 4 --quiet --out "$out" > "$out.log" 2>&1 || echo "FAILED $c $f"
done; done
