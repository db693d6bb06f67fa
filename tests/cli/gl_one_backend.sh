#!/usr/bin/env bash
# A build with one headless backend (docs/gpu.md; registered only in such a
# build, e.g. -DHW_WITH_OSMESA=OFF as on Mesa >= 25.1): `info` says which one
# was built and `--gl auto` takes it; a walk runs on it and its report names
# it; the other one, asked for by --gl or HYBRIDWALK_GL, is refused with one
# line naming the configure option and the backend to use; when the built one
# fails too (HW_GL_FAIL=1), the message gives both reasons and does not send
# the user to the backend that just failed.
# Usage: gl_one_backend.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"

"$hw" info >"$tmp/info.out" 2>&1
rc=$?; check "info exits 0 (got $rc)" test $rc -eq 0
built=$(sed -n 's/^headless OpenGL backends built: egl \(yes\|no\), osmesa \(yes\|no\)$/\1 \2/p' "$tmp/info.out")
case "$built" in
  "yes no") have=egl missing=osmesa Missing=OSMesa ;;
  "no yes") have=osmesa missing=egl Missing=EGL ;;
  *) have="" missing="" Missing="" ;;
esac
check "info: exactly one backend built ('$built')" test -n "$have"
check "info: --gl auto takes $have ($(tail -1 "$tmp/info.out"))" grep -q -- "--gl auto takes: $have" "$tmp/info.out"

machine() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["summary"]["machine"]["gl_backend"])' "$1"; }
"$hw" walk --scene indoor:20k --frames 6 --mode hybrid --strips 0 --quiet --out "$tmp/walk" >"$tmp/walk.out" 2>&1
rc=$?; check "walk exits 0 ($(tail -1 "$tmp/walk.out"))" test $rc -eq 0
check "walk report names $have" test "$(machine "$tmp/walk/report.json" 2>&1)" = "$have"

refused() {  # NAME OUTPUT_FILE RC
  check "$1 exits 1 (got $3)" test "$3" -eq 1
  check "$1: one line naming the build, the option and --gl $have ($(tail -1 "$2"))" \
    grep -q "^hybridwalk: error: this hybridwalk was built without $Missing (configure with -DHW_WITH_${Missing^^}=ON.*); use --gl $have\$" "$2"
  check "$1: nothing written" test ! -e "$tmp/refused"
}
"$hw" walk --gl $missing --frames 3 --quiet --out "$tmp/refused" >"$tmp/gl.out" 2>&1
refused "walk --gl $missing" "$tmp/gl.out" $?
HYBRIDWALK_GL=$missing "$hw" walk --frames 3 --quiet --out "$tmp/refused" >"$tmp/env.out" 2>&1
refused "HYBRIDWALK_GL=$missing walk" "$tmp/env.out" $?

HW_GL_FAIL=1 "$hw" walk --frames 3 --quiet --out "$tmp/refused" >"$tmp/fail.out" 2>&1
rc=$?; check "HW_GL_FAIL=1 walk exits 1 (got $rc)" test $rc -eq 1
check "HW_GL_FAIL=1: both reasons ($(tail -1 "$tmp/fail.out"))" \
  grep -q "no headless OpenGL 4.5 core context: EGL: .*; OSMesa: .*" "$tmp/fail.out"
check "HW_GL_FAIL=1: $have failed" grep -q "cannot create an $([ $have = egl ] && echo EGL || echo OSMesa) OpenGL context: HW_GL_FAIL=1" "$tmp/fail.out"
check "HW_GL_FAIL=1: $Missing not built" grep -q "built without $Missing (configure with" "$tmp/fail.out"
check "HW_GL_FAIL=1: does not suggest --gl $have" bash -c "! grep -q -- '--gl $have' '$tmp/fail.out'"
finish
