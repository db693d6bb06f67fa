#!/usr/bin/env bash
# Install what is missing, build, and run the whole test suite:
#  1. release build without OSMesa (EGL only, as on Mesa >= 25.1; warnings
#     as errors): every CTest (CPU, GL on EGL, the windowed GLFW tests under
#     Xvfb, command-line tests, the catalogue); then the library installed
#     without tests and both examples built against it
#     (scripts/test_install.sh);
#  2. the program built with both EGL and OSMesa (the release flags; with
#     ccache only the three backend files and a link): EGL and OSMesa write
#     identical frames, and walks on OSMesa (cli.gl_backends);
#  3. one clang build at -O1 under AddressSanitizer + UBSan (asan preset,
#     build-asan/): the CPU tests, the bad-input catalogue against the whole
#     program built that way, and
#  4. each libFuzzer target of that build for a bounded time from its
#     committed seed corpus, two at a time.
# HW_TEST_QUICK=1 runs step 1 only. HW_FUZZ_SECONDS sets step 4's time per target.
# HW_TEST_ASAN_CATALOGUE=0 leaves out step 3's catalogue run (local quick runs).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --test
# ccache when installed (setup.sh --test installs it): step 2's build with
# OSMesa then compiles only the files that differ. Build directories differ,
# so the directory is left out of the hash.
if command -v ccache >/dev/null; then
  export CMAKE_C_COMPILER_LAUNCHER=ccache CMAKE_CXX_COMPILER_LAUNCHER=ccache CCACHE_NOHASHDIR=1
fi
# Without OSMesa: the whole suite runs on EGL (a later scripts/build.sh keeps
# this setting; -DHW_WITH_OSMESA=ON turns it back on).
bash scripts/build.sh release -DHW_WERROR=ON -DHW_WITH_OSMESA=OFF
# Real scenes for the OpenArena test: apt-get download into the user cache
# (idempotent; nothing installed system-wide). Stale package lists: update once.
build/bin/hybridwalk scenes fetch --outdoor --quiet ||
  { apt-get update -qq && build/bin/hybridwalk scenes fetch --outdoor --quiet; }
# llvmpipe threads: 2 gave the steadiest figures here (NOTES-GL.md).
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}
log=$(mktemp)
trap 'rm -f "$log" "$log.a" "$log.b"' EXIT
# -noreset: by default Xvfb resets when its last client disconnects, and a
# client connecting during the reset is dropped ("Failed to open display"):
# the viewer tests close one window and open the next, two at a time. Seen
# twice in CI (ViewerAsync tests, sessions 6 and 7); xorg/xserver issue 1102.
(cd build && xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest --output-on-failure -j 2 --timeout 600) | tee -a "$log"
echo "== the installed library: examples built with find_package(hybridwalk)"
bash scripts/test_install.sh
[ "${HW_TEST_QUICK:-0}" = 1 ] && exit 0

echo "== with OSMesa beside EGL: identical frames on both, walks on OSMesa (docs/gpu.md)"
# The release build's flags with OSMesa found: only the three backend files
# differ, so with ccache (step 1 filled it) this is those files and one link.
cmake -S . -B build-both -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBUILD_TESTING=ON \
  -DHW_WITH_OSMESA=ON -DHW_WERROR=ON >/dev/null
cmake --build build-both -j "$(nproc)" --target hybridwalk
(cd build-both && ctest --output-on-failure -R '^cli\.gl_backends$' --no-tests=error) | tee -a "$log"

echo "== clang -O1 under AddressSanitizer + UndefinedBehaviorSanitizer: CPU tests, the bad-input catalogue, libFuzzer targets"
cpu_targets=$(for f in tests/cpu/*_test.cpp; do basename "$f" .cpp; done)
fuzzers=$(for f in */*_fuzz.cpp; do basename "$f" .cpp; done)
# One build for all three (every object carries libFuzzer's coverage
# instrumentation, which the tests do not use): a second sanitizer build
# for the fuzzers alone cost CI about as much as this one. Warnings are the
# GCC build's (step 1, -Werror).
cmake --preset asan >/dev/null
asan_catalogue=${HW_TEST_ASAN_CATALOGUE:-1}
extra_target=""
# The CPU tests already link every module, so the program adds only
# app/main.cpp and one link.
[ "$asan_catalogue" = 1 ] && extra_target=hybridwalk
# shellcheck disable=SC2086
cmake --build build-asan -j "$(nproc)" --target $cpu_targets $extra_target $fuzzers
(cd build-asan && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=halt_on_error=1:abort_on_error=1:print_stacktrace=1 \
  ctest --output-on-failure -j 2 -L cpu --timeout 600) | tee -a "$log"
# Every catalogue row against the sanitized program: a memory error or UB on
# bad input aborts (SIGABRT), which the row reports as a crash. UBSan's own
# abort_on_error: without it a UB report ends the program with exit 1, which
# a row expecting exit 1 only catches through its message. Not the rows
# that set `ulimit -v` (found in cases.tsv) (ASan reserves terabytes of address space for its
# shadow memory and cannot start under one); the release build runs them.
# Leaks are not checked here: OSMesa/llvmpipe and Assimp keep allocations to
# exit on the error paths (the CPU tests above check ours).
# -j 4 on 2 cores: a row keeps less than one core busy on average (process
# start, scene load, waits on children, FIFOs and signals).
if [ "$asan_catalogue" = 1 ]; then
  no_asan=$(awk -F'\t' '$6 ~ /ulimit -v/ {printf "%s%s", sep, $1; sep="|"}' tests/catalogue/cases.tsv)
  (cd build-asan && ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=halt_on_error=1:abort_on_error=1:print_stacktrace=1 \
    xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \
    ctest --output-on-failure -j 4 -L catalogue -E "^catalogue\\.($no_asan)\$" \
    --timeout 600) | tee -a "$log"
else
  echo "(HW_TEST_ASAN_CATALOGUE=0: the catalogue under ASan is left out)"
fi

echo "== libFuzzer targets (${HW_FUZZ_SECONDS:-20} s each, two at a time)"
# One target: its own scratch corpus (new inputs go there; the committed
# seeds are only read) and log; the log's summary lines, or its tail on failure.
fuzz_one() {
  local fz=$1 seeds=tests/fuzz/${1%_fuzz} work status=0
  work=$(mktemp -d)
  build-asan/bin/"$fz" -max_total_time="${HW_FUZZ_SECONDS:-20}" -timeout=10 -rss_limit_mb=4096 \
    -print_final_stats=1 "$work" "$seeds" >"$work.log" 2>&1 || status=$?
  {
    echo "-- $fz (seeds: $seeds)"
    grep -E "stat::number_of_executed_units|ERROR|SUMMARY|==[0-9]+==|Done" "$work.log" | head -40 || true
    if [ "$status" -ne 0 ]; then tail -60 "$work.log"; echo "$fz failed (exit $status)"; fi
  } >"$work.out"
  cat "$work.out"
  rm -rf "$work" "$work.log" "$work.out"
  return "$status"
}
failed=0
set -- $fuzzers
while [ $# -gt 0 ]; do
  fuzz_one "$1" >"$log.a" &
  pa=$!
  pb=""
  if [ $# -gt 1 ]; then
    fuzz_one "$2" >"$log.b" &
    pb=$!
  fi
  wait "$pa" || failed=1
  cat "$log.a"
  if [ -n "$pb" ]; then
    wait "$pb" || failed=1
    cat "$log.b"
    shift
  fi
  shift
done
rm -f "$log.a" "$log.b"
[ "$failed" = 0 ] || exit 1
nfuzz=$(echo "$fuzzers" | wc -w)
nctest=$(awk '/tests passed, 0 tests failed out of/ { n += $NF } END { print n + 0 }' "$log")
echo "sanitizers and fuzzers: all passed"
# One closing line for the whole run: CTest (release + ASan) plus the fuzzers.
echo "total: $((nctest + nfuzz)) passed, 0 failed"
