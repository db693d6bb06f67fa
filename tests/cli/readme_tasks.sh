#!/usr/bin/env bash
# The README's common tasks do what the README says, run as written from the
# root of a fresh clone (one per README block), on built-in scenes at a
# small size (160x120, 21 frames, unless a command sets its own; task 1's
# walk at its own): every command exits 0; each walk ends with its summary
# line, writes index.html and prints no "nan"; the indoor walk of task 1
# warps frames and writes strips and frames; the sweeps (the full one too)
# say which pipeline they ran; the viewer's screenshot is a warped frame;
# afterwards nothing is left in a clone outside out/, and out/ is ignored.
# The commands that need downloaded scenes (q3:, torcs:, `scenes`) are
# readme_tasks_maps.sh's: between the two, every README command runs.
# Usage: readme_tasks.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
source "$(dirname "$0")/readme_lib.bash"
src=$2
readme_commands "$src" >"$tmp/all"
check "README has task commands ($(wc -l <"$tmp/all"))" test "$(wc -l <"$tmp/all")" -ge 15
grep -vE "$readme_maps_re" "$tmp/all" >"$tmp/run"
small=' --width 160 --height 120 --frames 21'
task() {
  local cmd=$1
  # Task 1's walk runs as written (512x512, 120 frames, about 10 s): the
  # choice to warp is measured, and at its own size it is clear-cut.
  case "$cmd" in
    *"--out out/indoor") ;;
    *"hybridwalk walk"* | *"hybridwalk sweep"* | *"hybridwalk bake"*)
      [[ "$cmd" == *--width* ]] || cmd="$cmd$small" ;;
  esac
  cmd=${cmd/--exit-after 120/--exit-after 24}
  [[ "$cmd" == *"hybridwalk view"* ]] && cmd="$cmd --width 160 --height 120"
  readme_run "$cmd"
  [[ "$cmd" == *"hybridwalk view"*--screenshot* ]] && check "  the screenshot is a warped frame" \
    grep -Eq "last frame: hybrid, (one keyframe|two keyframes) warped" "$last_out"
}
readme_each "$src" "$tmp/run" task
check "the full sweep ran (all variants and baselines)" \
  grep -Eq "^sweep: [0-9]+ runs of the default pipeline.*open out/sweep/index.html" <(cat "$tmp"/out*)
# Task 1 shows warping: warped frames, and strips of them.
warped=$(readme_summary out/indoor 's["frames_by_mode"]["warp"]')
check "task 1 warps frames ($warped)" test "$warped" -gt 0 2>/dev/null
check "task 1 writes strips" bash -c 'ls "$(dirname "$1")"/strip_*.png >/dev/null 2>&1' _ \
  "$(readme_file out/indoor/report.json)"
check "task 1 writes every frame (--save-frames)" test -s "$(readme_file out/indoor/frames/0000.png)"
check "task 5 screenshot" test -s "$(readme_file out/view.png)"
check "task 6 path file under out/" python3 -c 'import json,sys; json.load(open(sys.argv[1]))' \
  "$(readme_file out/my_path.json)"
check "publish wrote its site" test -s "$(readme_file out/site/indoor/index.html)"
blocks=$(cut -f1 "$tmp/run" | sort -u | wc -l)
check "one fresh clone per block ($readme_clones for $blocks)" test "$readme_clones" -eq "$blocks" -a "$blocks" -ge 6
finish
