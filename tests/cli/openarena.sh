#!/usr/bin/env bash
# A real OpenArena map (scripts/test.sh fetched the packages into the cache
# first): oa_dm5 loads with its patches, and a short hybrid walk through it
# reaches a sane quality. Usage: openarena.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
"$hw" scenes list >"$tmp/list" 2>&1
check "oa_dm5 is in the cache (run scripts/test.sh or 'hybridwalk scenes fetch')" grep -Eq '^q3 +q3:oa_dm5 ' "$tmp/list"
check "all 50 maps listed" test "$(grep -c '^q3 ' "$tmp/list")" -eq 50
"$hw" walk --mode hybrid --scene q3:oa_dm5 --frames 21 --strips 1 --out "$tmp/w" --quiet >"$tmp/out" 2>"$tmp/err"
rc=$?; check "walk exits 0 ($(tail -2 "$tmp/err"))" test $rc -eq 0
check "107k triangles (107414 + 14 of sky)" grep -q "oa_dm5: 107428 triangles" "$tmp/err"
psnr=$(sed -n 's/^  warped frames: PSNR median \([0-9.]*\) dB.*/\1/p' "$tmp/out")
check "median in-between PSNR >= 28 dB (got $psnr)" awk -v p="$psnr" 'BEGIN { exit !(p >= 28) }'
check "strip written" test -n "$(ls "$tmp/w"/strip_*.png 2>/dev/null)"
"$hw" walk --scene q3:no_such_map --out "$tmp/x" --quiet >/dev/null 2>"$tmp/err2"
check "unknown map refused" test $? -ne 0
check "unknown map message names it" grep -q "no_such_map" "$tmp/err2"
finish
