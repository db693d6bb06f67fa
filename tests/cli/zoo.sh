#!/usr/bin/env bash
# A handful of the scene zoo (scripts/zoo.sh): an OpenArena map, a road, a
# dirt and an oval TORCS track (from their track descriptions) and a MORSE
# terrain walk from their default paths with the eye in playable space, and
# `scenes list` naming every kind. Needs `hybridwalk scenes fetch --outdoor`.
# Usage: zoo.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
src=$2
"$hw" scenes list >"$tmp/list" 2>&1
for k in built-in q3 torcs morse; do
  check "scenes list has $k entries" grep -q "^$k " "$tmp/list"
done
check "scenes list marks nothing unfetched here" sh -c "! grep -q 'NOT FETCHED' '$tmp/list'"
bash "$src/scripts/zoo.sh" --hw "$hw" --out "$tmp/zoo" --frames 8 \
  --only q3:oa_dm5,torcs:e-track-3,torcs:dirt-2,torcs:michigan,morse:land-1/buildings_1 2>"$tmp/err"
check "zoo passes ($(tail -1 "$tmp/err"))" test $? -eq 0
check "five rows" test "$(($(wc -l <"$tmp/zoo/zoo.csv") - 1))" -eq 5
check "every row ok" test "$(grep -c ',ok,' "$tmp/zoo/zoo.csv")" -eq 5
check "eyes above a floor" test "$(grep -c ',yes,ok,' "$tmp/zoo/zoo.csv")" -eq 5
check "contact sheet written" test -s "$tmp/zoo/contact_sheet.png"
finish
