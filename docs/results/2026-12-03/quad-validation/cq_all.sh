#!/bin/bash
# usage: cq_all.sh OUT  -- check-quads, default preset, every scene/path
# Run from the repository root; the program at $HW (build/bin/hybridwalk).
OUT=$1; HW=${HW:-build/bin/hybridwalk}; export LP_NUM_THREADS=2; mkdir -p $OUT
cases="indoor:100k| indoor:100k|paths/indoor_sharp_turn.json outdoor:100k| q3:oa_dm5|paths/oa_dm5.json
q3:aggressor|paths/aggressor.json q3:delta|paths/delta.json q3:oa_dm1|paths/oa_dm1.json
q3:ps37ctf|paths/ps37ctf.json torcs:forza|paths/forza.json torcs:e-track-2|paths/e-track-2.json
torcs:ruudskogen|paths/ruudskogen.json morse:land-1/trees|paths/trees.json"
for c in $cases; do
  sc=${c%%|*}; p=${c#*|}; pa=""; [ -n "$p" ] && pa="--path $p"
  tag=$(echo "$sc${p:+_$(basename "$p" .json)}" | tr ':/' '__')
  $HW check-quads --scene "$sc" $pa --quiet --out "$OUT/$tag" 2>&1 | tail -1
done
