#!/usr/bin/env bash
# The README's tasks on downloaded scenes (scripts/test.sh fetched OpenArena
# and TORCS into the cache first), run as written from the root of a fresh
# clone (one per README block), at their own sizes: `scenes fetch` (nothing
# to download: the cache is full), `scenes list`, the oa_dm5 and forza walks
# (task 2), the oa_dm5 bake and the walk from it (task 4), and the desktop
# viewer command under Xvfb (stopped after 24 frames). Every command exits 0
# without "nan"; each walk prints its summary line first and writes
# index.html; the forza walk (`--mode hybrid`) warps what the README says
# (215 of 240 frames, median 30.7 dB) and writes strips; the walk from the
# database reads its keyframes from it; nothing is left outside out/.
# Usage: readme_tasks_maps.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
source "$(dirname "$0")/readme_lib.bash"
src=$2
readme_commands "$src" | grep -E "$readme_maps_re" >"$tmp/run"
check "README has tasks on downloaded scenes ($(wc -l <"$tmp/run"))" test "$(wc -l <"$tmp/run")" -ge 7
"$hw" scenes list >"$tmp/list" 2>&1
check "oa_dm5 and forza are in the cache (run scripts/test.sh or 'hybridwalk scenes fetch --outdoor')" \
  bash -c 'grep -Eq "^q3 +q3:oa_dm5 " "$1" && grep -q "torcs:forza" "$1"' _ "$tmp/list"
task() {
  local cmd=$1
  # The viewer "on a desktop": under Xvfb, a few frames.
  [[ "$cmd" == "hybridwalk view"* ]] && cmd="xvfb-run -a $cmd --play --exit-after 24"
  readme_run "$cmd"
}
readme_each "$src" "$tmp/run" task
# Task 2: the forza walk in --mode hybrid warps what the README says.
readme_line() {  # the line of the README's task 2 paragraph that quotes it
  grep -o "[0-9.]* dB[[:space:]]*median, [0-9]* of [0-9]* frames warped" <(tr '\n' ' ' <"$src/README.md")
}
promise=$(readme_line)
check "the README quotes the forza walk ($promise)" test -n "$promise"
want_db=$(sed 's/ dB.*//' <<<"$promise")
want_warped=$(sed 's/.*median, \([0-9]*\) of.*/\1/' <<<"$promise")
want_frames=$(sed 's/.* of \([0-9]*\) frames.*/\1/' <<<"$promise")
got_warped=$(readme_summary out/forza 's["frames_by_mode"]["warp"]')
got_frames=$(readme_summary out/forza 's["frames"]')
got_db=$(readme_summary out/forza '"%.1f" % s["psnr"]["median"]')
check "forza: $got_warped of $got_frames frames warped (README: $want_warped of $want_frames)" \
  test "$got_warped" = "$want_warped" -a "$got_frames" = "$want_frames"
check "forza: median $got_db dB (README: $want_db dB)" test "$got_db" = "$want_db"
check "forza: strips written" bash -c 'ls "$(dirname "$1")"/strip_*.png >/dev/null 2>&1' _ \
  "$(readme_file out/forza/report.json)"
# Task 4: the walk from the database reads its keyframes there.
check "task 4: the bake wrote a database" test -s "$(readme_file out/db/oa_dm5/index.json)"
acq=$(readme_summary out/oa_db 's["keyframe_acquisition"]')
check "task 4: the walk takes its keyframes from the database ($acq)" test "$acq" = source
check "task 4: it says so" grep -Eq "keyframes: [0-9]+ in the schedule \(the database's\), [0-9]+ read from the database" \
  <(cat "$tmp"/out*)
finish
