#!/bin/bash
# Quad validation over every scene and path we have, without and with the
# split (check-quads --split-misfit off|on, default preset otherwise), then
# the walk at the default preset in hybrid mode (every frame warped) before
# and after. HW: this branch's program; HW_BEFORE: the program built from the
# commit before the split (026e8df), for the walks' "before" column.
# Usage: run.sh OUT   (then table.py OUT prints the tables of README.md)
set -u
HW=${HW:-build/bin/hybridwalk}
HW_BEFORE=${HW_BEFORE:-/tmp/wtv/hw-before}
OUT=${1:-/tmp/qv}
export LP_NUM_THREADS=2
mkdir -p "$OUT/check" "$OUT/walk"
cases="indoor:100k| indoor:100k|paths/indoor_sharp_turn.json outdoor:100k| q3:oa_dm5|paths/oa_dm5.json
q3:aggressor|paths/aggressor.json q3:delta|paths/delta.json q3:oa_dm1|paths/oa_dm1.json
q3:ps37ctf|paths/ps37ctf.json torcs:forza|paths/forza.json torcs:e-track-2|paths/e-track-2.json
torcs:ruudskogen|paths/ruudskogen.json morse:land-1/trees|paths/trees.json"
if [ "${SKIP_CHECK:-0}" != 1 ]; then
  for c in $cases; do
    sc=${c%%|*}; p=${c#*|}; pa=""; [ -n "$p" ] && pa="--path $p"
    tag=$(echo "$sc${p:+_$(basename "$p" .json)}" | tr ':/' '__')
    for split in off on; do
      [ -f "$OUT/check/${tag}_$split/report.json" ] && continue  # done in an earlier run
      nice -n 5 $HW check-quads --scene "$sc" $pa --split-misfit $split --quiet \
        --out "$OUT/check/${tag}_$split" > "$OUT/check/${tag}_$split.log" 2>&1 ||
        echo "check $tag $split failed" >&2
    done
  done
fi
if [ "${SKIP_WALK:-0}" != 1 ]; then
  for c in "indoor:100k|" "q3:oa_dm5|paths/oa_dm5.json" "torcs:forza|paths/forza.json" "outdoor:100k|"; do
    sc=${c%%|*}; p=${c#*|}; pa=""; [ -n "$p" ] && pa="--path $p"
    tag=$(echo "$sc" | tr ':/' '__')
    for which in before after; do
      [ -f "$OUT/walk/${tag}_$which/report.json" ] && continue
      bin=$HW; [ $which = before ] && bin=$HW_BEFORE
      nice -n 5 $bin walk --scene "$sc" $pa --preset default --mode hybrid --frames 120 --strips 0 \
        --quiet --out "$OUT/walk/${tag}_$which" > "$OUT/walk/${tag}_$which.log" 2>&1 ||
        echo "walk $tag $which failed" >&2
    done
  done
fi
