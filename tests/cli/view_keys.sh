#!/usr/bin/env bash
# view's keys as docs/viewer.md lists them: scripted keys (--keys) reach any
# frame with '@N' marks (p measures the PSNR of frames 5 and 12, not frame
# 0); s goes fps -> per-stage -> keyframe stalls -> off, so a second s shows
# the stalls; bad marks are usage errors (exit 2) before the scene loads;
# every key of the h help is in view --help. Runs under Xvfb (scripts/test.sh
# runs CTest in xvfb-run).
# Usage: view_keys.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
cd "$tmp"
common=(--scene indoor:20k --play --width 160 --height 120 --preset paper)

"$hw" view "${common[@]}" --exit-after 14 --keys 's@5p@12pss' >keys.out 2>&1
rc=$?; check "scripted session exits 0 ($(tail -1 keys.out))" test $rc -eq 0
check "p before frame 5 measures frame 5" grep -Eq '^PSNR [0-9.]+ dB vs geometry \(hybrid, frame 5\)$' keys.out
check "p before frame 12 measures frame 12" grep -Eq '^PSNR [0-9.]+ dB vs geometry \(hybrid, frame 12\)$' keys.out
check "no PSNR of other frames" test "$(grep -c '^PSNR' keys.out)" -eq 2
check "s, s, s: stages, then stalls, then off" bash -c '
  grep "^statistics" "$1" | tr "\n" "|" | grep -qx \
    "statistics: fps, per-stage ms, quads, holes|statistics: fps, per-stage ms, quads, holes, keyframe stalls and waits|statistics off|"' _ keys.out

bad() {  # NAME REGEX ARGS...
  local name=$1 re=$2; shift 2
  "$hw" view --scene no_such_scene "$@" >bad.out 2>&1
  local rc=$?
  check "$name exits 2 (got $rc)" test $rc -eq 2
  check "$name message ($(head -1 bad.out))" grep -Eq -- "$re" bad.out
}
bad "--keys s@" "^hybridwalk: error: --keys: keys 's@'.*frame number" --keys 's@'
bad "--keys @9p@3p" "^hybridwalk: error: --keys: .*must not decrease" --keys '@9p@3p'

# Every key h lists ("  KEY    action") appears, with its action, in --help.
"$hw" view "${common[@]}" --no-hud --exit-after 1 --keys h >help_key.out 2>&1
check "h prints the keys" grep -q "hybridwalk viewer keys" help_key.out
"$hw" view --help | tr '\n' ' ' | tr -s ' ' >help.txt
keys=$(sed -n '/hybridwalk viewer keys/,/^  p /p' help_key.out | grep -E '^  [^ ]+ {2,}' | awk '{print $1}')
check "h lists at least 13 keys" test "$(wc -w <<<"$keys")" -ge 13
for k in $keys; do
  check "view --help lists key $k" grep -qE "[:,] $k [a-zA-Z]" help.txt
done
check "view --help lists f full screen" grep -q ", f full screen," help.txt
finish
