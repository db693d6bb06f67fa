#!/usr/bin/env bash
# A short soak (scripts/soak.sh) in every CI run: 3,000 frames at
# 128², one lap. Catches memory that grows with the frames walked — e.g. a
# keyframe cache that keeps passed keyframes until its byte bound (300
# keyframes here would add ~60 MiB, far above the 5 % limit).
# Usage: soak_short.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
src=$2
bash "$src/scripts/soak.sh" --hw "$hw" --frames 3000 --size 128x128 --laps 1 --out "$tmp/soak" \
  >"$tmp/soak.out" 2>&1
rc=$?
tail -4 "$tmp/soak.out"
check "soak passes (exit $rc)" test $rc -eq 0
check "soak printed its verdict" grep -q "soak: PASS" "$tmp/soak.out"
finish
