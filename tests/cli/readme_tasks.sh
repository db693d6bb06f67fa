#!/usr/bin/env bash
# The README's common tasks do what the README says, run as written (in a
# scratch folder, on built-in scenes, at a small size): every command exits
# 0; each walk ends with its summary line, writes index.html and prints no
# "nan"; the indoor walk of task 1 warps frames and writes strips; the sweep
# says which pipeline it ran; everything lands under out/. Tasks that need
# downloaded scenes (q3:, torcs:) or a desktop are left out.
# Usage: readme_tasks.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
src=$2
mkdir -p "$tmp/bin" "$tmp/work"
ln -s "$(readlink -f "$hw")" "$tmp/bin/hybridwalk"
export PATH="$tmp/bin:$PATH"
# The commands of the README's ```sh blocks, one per line, comments cut.
awk '/^```sh/{on=1; next} /^```/{on=0} on' "$src/README.md" | sed 's/[[:space:]]*#.*$//' |
  grep -E '^(hybridwalk|python3|mkdir|xvfb-run)' >"$tmp/all"
check "README has task commands" test "$(wc -l <"$tmp/all")" -ge 8
grep -vE 'q3:|torcs:|scenes fetch|^hybridwalk view' "$tmp/all" |
  grep -vE '^hybridwalk sweep( --scene [^ ]+)? --out [^ ]+$' >"$tmp/run"  # the full sweep: 67 walks
# Small and short: built-in scenes at 160x120, 21 frames (a command that sets
# its own size keeps it).
small=' --width 160 --height 120 --frames 21'
n=0
while IFS= read -r cmd; do
  n=$((n + 1))
  case "$cmd" in
    *"hybridwalk walk"* | *"hybridwalk sweep"*) [[ "$cmd" == *--width* ]] || cmd="$cmd$small" ;;
  esac
  cmd=${cmd/--exit-after 120/--exit-after 24}
  [[ "$cmd" == *"hybridwalk view"* ]] && cmd="$cmd --width 160 --height 120"
  (cd "$tmp/work" && bash -c "$cmd") >"$tmp/out$n" 2>"$tmp/err$n"
  rc=$?
  check "exits 0: $cmd ($(tail -1 "$tmp/err$n"))" test $rc -eq 0
  check "  no nan: $cmd" bash -c '! grep -qiw nan "$1" "$2"' _ "$tmp/out$n" "$tmp/err$n"
  [[ "$cmd" == *"hybridwalk view"*--screenshot* ]] && check "  the screenshot is a warped frame" \
    grep -Eq "last frame: hybrid, (one keyframe|two keyframes) warped" "$tmp/out$n"
  if [[ "$cmd" == *"hybridwalk walk"* ]]; then
    out=$(sed -n 's/.*--out \([^ ]*\).*/\1/p' <<<"$cmd")
    check "  summary line first: $(head -1 "$tmp/out$n")" \
      grep -qE '^[^ ]+, [0-9]+ frames: (([0-9]+|<1) % warped|none warped \(.+\))' "$tmp/out$n"
    check "  index.html beside report.json" test -s "$tmp/work/$out/index.html" -a -s "$tmp/work/$out/report.json"
  fi
  if [[ "$cmd" == *"hybridwalk sweep"* ]]; then
    check "  the sweep names its pipeline" grep -q "runs of the default pipeline" "$tmp/out$n"
    out=$(sed -n 's/.*--out \([^ ]*\).*/\1/p' <<<"$cmd")
    check "  its page too" grep -q "the default pipeline" "$tmp/work/$out/index.html"
  fi
done <"$tmp/run"
# Task 1 shows warping: warped frames, and strips of them.
warped=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["summary"]["frames_by_mode"]["warp"])' \
  "$tmp/work/out/indoor/report.json" 2>/dev/null || echo 0)
check "task 1 warps frames ($warped)" test "$warped" -gt 0
check "task 1 writes strips" bash -c 'ls "$1"/strip_*.png >/dev/null 2>&1' _ "$tmp/work/out/indoor"
check "task 1 writes every frame (--save-frames)" test -s "$tmp/work/out/indoor/frames/0000.png"
check "task 5 screenshot" test -s "$tmp/work/out/view.png"
check "task 6 path file under out/" python3 -c 'import json,sys; json.load(open(sys.argv[1]))' "$tmp/work/out/my_path.json"
# Nothing outside out/.
stray=$(cd "$tmp/work" && ls -A | grep -vx out | tr '\n' ' ')
check "nothing written outside out/ ($stray)" test -z "$stray"
finish
