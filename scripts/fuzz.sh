#!/usr/bin/env bash
# Longer libFuzzer runs for people (CI runs each target for 20 s in
# scripts/test.sh, from the asan preset's build). Builds the `fuzz` preset (clang; build dir build-fuzz;
# the whole build instrumented with coverage + ASan + UBSan), then runs each
# target, or the ones named, for a fixed wall-clock time starting from its
# committed seed corpus tests/fuzz/NAME/ (only read). New inputs go to a
# scratch corpus WORK/NAME/corpus, crashing/leaking/slow inputs to
# WORK/NAME/crashes/, the log to WORK/NAME/log. A summary table gives
# executions, executions per second, new inputs and coverage per target.
#
# Usage: scripts/fuzz.sh [options] [NAME...]
#   NAME            camera_path, q3bsp, lod, torcs_track, keyframe_db, acc,
#                   q3shader, json_guard, texture (the */NAME_fuzz.cpp targets);
#                   default: all of them, one after another
#   --time S        seconds per target (default 600 = 10 minutes)
#   --unit-timeout S  an input running longer counts as a failure (default
#                   10; wall-clock time: at nice 19 on a loaded machine a
#                   0.3 s input took over 10 s, so raise it there)
#   --work DIR      scratch corpora, crashes and logs (default out/fuzz;
#                   kept between runs, so a second run continues the first)
#   --merge         afterwards, copy the scratch inputs that add coverage into
#                   tests/fuzz/NAME/ (libFuzzer -merge=1) to be committed; the
#                   seeds are few, so a first merge adds hundreds of files
#                   (797 after 5 s of camera_path): look before committing
#   --no-build      use the existing build-fuzz binaries
#   -h, --help      this text
# Exit status: 0 no target failed, 1 a target crashed/leaked/timed out (see
# WORK/NAME/crashes/ and reproduce with build-fuzz/bin/NAME_fuzz FILE),
# 2 bad command line or build failure.
set -u
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$here" || exit 2
seconds=600
unit_timeout=10
work=out/fuzz
merge=0
build=1
names=()
while [ $# -gt 0 ]; do
  case $1 in
    --time) seconds=${2:-}; shift 2 || { echo "fuzz.sh: --time needs a value" >&2; exit 2; } ;;
    --unit-timeout) unit_timeout=${2:-}; shift 2 || { echo "fuzz.sh: --unit-timeout needs a value" >&2; exit 2; } ;;
    --work) work=${2:-}; shift 2 || { echo "fuzz.sh: --work needs a value" >&2; exit 2; } ;;
    --merge) merge=1; shift ;;
    --no-build) build=0; shift ;;
    -h|--help) sed -n '2,29p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "fuzz.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) names+=("${1%_fuzz}"); shift ;;
  esac
done
if ! [[ $seconds =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ]; then
  echo "fuzz.sh: --time: expected whole seconds >= 1, got '$seconds'" >&2; exit 2
fi
if ! [[ $unit_timeout =~ ^[0-9]+$ ]] || [ "$unit_timeout" -lt 1 ]; then
  echo "fuzz.sh: --unit-timeout: expected whole seconds >= 1, got '$unit_timeout'" >&2; exit 2
fi
[ -n "$work" ] || { echo "fuzz.sh: --work: expected a directory, got ''" >&2; exit 2; }

all=$(for f in */*_fuzz.cpp; do basename "$f" _fuzz.cpp; done)
all_line=$(tr '\n' ' ' <<<"$all")
[ ${#names[@]} -gt 0 ] || read -r -a names <<<"$all_line"
for n in "${names[@]}"; do
  grep -qx "$n" <<<"$all" ||
    { echo "fuzz.sh: no fuzz target '$n' (have: ${all_line% })" >&2; exit 2; }
  [ -d "tests/fuzz/$n" ] || { echo "fuzz.sh: no seed corpus tests/fuzz/$n/" >&2; exit 2; }
done
targets=$(printf '%s_fuzz ' "${names[@]}")

if [ $build -eq 1 ]; then
  command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ is needed (bash scripts/setup.sh --test)" >&2; exit 2; }
  echo "fuzz: building $targets(preset fuzz, build-fuzz/)"
  cmake --preset fuzz >/dev/null || { echo "fuzz.sh: cmake --preset fuzz failed" >&2; exit 2; }
  # shellcheck disable=SC2086
  cmake --build build-fuzz -j "$(nproc 2>/dev/null || echo 2)" --target $targets ||
    { echo "fuzz.sh: build failed" >&2; exit 2; }
fi

mkdir -p "$work" || { echo "fuzz.sh: cannot create $work" >&2; exit 2; }
summary=$(mktemp)
trap 'rm -f "$summary"' EXIT
failed=0
for n in "${names[@]}"; do
  bin=build-fuzz/bin/${n}_fuzz
  [ -x "$bin" ] || { echo "fuzz.sh: no $bin (build without --no-build)" >&2; exit 2; }
  dir=$work/$n
  mkdir -p "$dir/corpus" "$dir/crashes"
  before=$(find "$dir/crashes" -type f | wc -l)
  echo "fuzz: $n for $seconds s (seeds tests/fuzz/$n/, new inputs $dir/corpus/, crashes $dir/crashes/)"
  status=0
  # Scratch corpus first: libFuzzer writes new inputs into the first directory.
  "$bin" -max_total_time="$seconds" -timeout="$unit_timeout" -rss_limit_mb=4096 -print_final_stats=1 \
    -artifact_prefix="$dir/crashes/" "$dir/corpus" "tests/fuzz/$n" >"$dir/log" 2>&1 || status=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$dir/log" | tail -1)
  added=$(sed -n 's/^stat::new_units_added: *//p' "$dir/log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$dir/log" | tail -1 | cut -d' ' -f2)
  crashes=$(($(find "$dir/crashes" -type f | wc -l) - before))
  result=ok
  if [ $status -ne 0 ]; then
    result="FAIL (exit $status)"
    failed=1
    grep -E "^==[0-9]+==ERROR|SUMMARY|Test unit written" "$dir/log" | head -5 | sed 's/^/  /'
  fi
  merged=-
  if [ $merge -eq 1 ] && [ $status -eq 0 ]; then
    m0=$(find "tests/fuzz/$n" -type f | wc -l)
    if "$bin" -merge=1 "tests/fuzz/$n" "$dir/corpus" >"$dir/merge.log" 2>&1; then
      merged=$(($(find "tests/fuzz/$n" -type f | wc -l) - m0))
    else
      merged="failed (see $dir/merge.log)"
      failed=1
    fi
  fi
  printf '%-12s %12s %10s %8s %6s %8s %8s  %s\n' "$n" "${execs:-?}" "${rate:-?}" "${added:-?}" \
    "${cov:-?}" "$crashes" "$merged" "$result" >>"$summary"
done

echo
printf '%-12s %12s %10s %8s %6s %8s %8s  %s\n' target executions "execs/s" "new" cov crashes merged result
cat "$summary"
echo "($seconds s per target; executions from libFuzzer's -print_final_stats; new = inputs added to"
echo " $work/NAME/corpus this run; merged = files --merge added to tests/fuzz/NAME/)"
exit $failed
