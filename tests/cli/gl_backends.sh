#!/usr/bin/env bash
# Headless backends (docs/gpu.md): the same indoor walk drawn through EGL and
# through OSMesa writes byte-identical frames (both are Mesa's llvmpipe here);
# each report's machine block names its backend; `--gl auto` and `info` take
# EGL on this machine; HYBRIDWALK_GL picks the backend; a walk with the
# keyframe worker (a second context on another thread) runs on each backend.
# Usage: gl_backends.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
# Modes and keyframes pinned (no timing-dependent choice), every frame saved.
common=(--scene indoor --frames 12 --mode hybrid --strips 0 --save-frames --quiet)
for b in egl osmesa; do
  "$hw" walk "${common[@]}" --gl $b --out "$tmp/$b" >"$tmp/$b.out" 2>&1
  rc=$?; check "walk --gl $b exits 0 ($(tail -2 "$tmp/$b.out"))" test $rc -eq 0
done
n=$(ls "$tmp/egl/frames" 2>/dev/null | wc -l)
check "egl walk saved frames ($n files)" test "$n" -ge 12
same=0; differ=""
for f in "$tmp/egl/frames"/*; do
  g="$tmp/osmesa/frames/$(basename "$f")"
  if cmp -s "$f" "$g"; then same=$((same + 1)); else differ="$differ $(basename "$f")"; fi
done
check "every frame identical on egl and osmesa ($same of $n same; differ:${differ:- none})" test -z "$differ"
machine() { python3 -c 'import json,sys; m=json.load(open(sys.argv[1]))["summary"]["machine"]; print(m["gl_backend"], "|", m["gl_vendor"], "|", m["gl_renderer"], "|", m["gl_version"])' "$1"; }
me=$(machine "$tmp/egl/report.json"); mo=$(machine "$tmp/osmesa/report.json")
check "egl report names egl and llvmpipe ($me)" grep -qE '^egl \| Mesa.* \| llvmpipe.* \| 4\.5 \(Core Profile\)' <<<"$me"
check "osmesa report names osmesa ($mo)" grep -qE '^osmesa \| .+ \| llvmpipe.* \| 4\.5 \(Core Profile\)' <<<"$mo"

"$hw" info >"$tmp/info.out" 2>&1
rc=$?; check "info exits 0" test $rc -eq 0
check "info: auto takes egl ($(tail -1 "$tmp/info.out"))" grep -q -- "--gl auto takes: egl" "$tmp/info.out"
check "info lists EGL device 0 with 4.5 core" \
  python3 -c 'import sys,re; t=open(sys.argv[1]).read(); sys.exit(0 if re.search(r"EGL device 0 .*\n(  .*\n)*  4\.5 core: yes", t) else 1)' "$tmp/info.out"
check "info lists OSMesa" grep -q "^OSMesa" "$tmp/info.out"
"$hw" info --gl egl --gl-device 0 >"$tmp/info0.out" 2>&1
check "info --gl egl --gl-device 0 takes egl" grep -q -- "--gl egl --gl-device 0 takes: egl" "$tmp/info0.out"

# HYBRIDWALK_GL picks the backend; --gl overrides it.
HYBRIDWALK_GL=osmesa "$hw" walk --scene indoor:20k --frames 3 --strips 0 --quiet --out "$tmp/env" >"$tmp/env.out" 2>&1
check "HYBRIDWALK_GL=osmesa walk runs on osmesa" grep -q '^osmesa ' <<<"$(machine "$tmp/env/report.json" 2>&1)"
HYBRIDWALK_GL=osmesa "$hw" walk --scene indoor:20k --frames 3 --strips 0 --quiet --gl egl --out "$tmp/over" >"$tmp/over.out" 2>&1
check "--gl egl overrides HYBRIDWALK_GL=osmesa" grep -q '^egl ' <<<"$(machine "$tmp/over/report.json" 2>&1)"

# The keyframe worker's second context, on each backend.
for b in egl osmesa; do
  "$hw" walk --scene indoor:20k --frames 12 --mode hybrid --async-keyframes --strips 0 --quiet --gl $b \
    --out "$tmp/async-$b" >"$tmp/async-$b.out" 2>&1
  rc=$?; check "async-keyframes walk --gl $b exits 0 ($(tail -2 "$tmp/async-$b.out"))" test $rc -eq 0
done
finish
