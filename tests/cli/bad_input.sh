#!/usr/bin/env bash
# Bad input to the program: each case must exit non-zero with a message that
# names what is wrong, and leave nothing in the output directory.
# Usage: bad_input.sh HYBRIDWALK SOURCE_DIR
set -u
hw=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
passed=0

# expect_fail NAME PATTERN ARGS... : non-zero exit, stderr matches PATTERN,
# and $tmp/out has no files.
expect_fail() {
  local name=$1 pattern=$2
  shift 2
  rm -rf "$tmp/out"
  "$hw" "$@" >"$tmp/stdout" 2>"$tmp/stderr" </dev/null
  local code=$?
  local ok=1
  if [ $code -eq 0 ]; then echo "FAIL $name: exit 0"; ok=0; fi
  if [ $code -ge 128 ]; then echo "FAIL $name: crashed (exit $code)"; ok=0; fi
  if ! grep -qiE -- "$pattern" "$tmp/stderr"; then
    echo "FAIL $name: stderr does not match /$pattern/:"; sed 's/^/    /' "$tmp/stderr"; ok=0
  fi
  if [ -d "$tmp/out" ] && [ -n "$(find "$tmp/out" -type f)" ]; then
    echo "FAIL $name: files left in output dir:"; find "$tmp/out" -type f | sed 's/^/    /'; ok=0
  fi
  if [ $ok -eq 1 ]; then passed=$((passed + 1)); else failures=$((failures + 1)); fi
}

path() {  # path NAME JSON
  printf '%s' "$2" >"$tmp/$1.json"
  echo "$tmp/$1.json"
}
good='"keys":[{"eye":[0,1.7,0],"look_at":[0,1.7,-5]},{"eye":[1,1.7,-1],"look_at":[1,1.7,-6]}]'

expect_fail unknown-scene "nope.*(indoor|built-in)" walk --scene nope --out "$tmp/out" --quiet
expect_fail missing-scene-file "missing\.obj" walk --scene "$tmp/missing.obj" --out "$tmp/out" --quiet
printf 'v 0 0 0\nv 1 0\nf 1 2 3 4 5\n' >"$tmp/trunc.obj"
expect_fail truncated-obj "trunc\.obj" walk --scene "$tmp/trunc.obj" --out "$tmp/out" --quiet
printf 'hello' >"$tmp/scene.xyz123"
expect_fail unsupported-scene "scene\.xyz123" walk --scene "$tmp/scene.xyz123" --out "$tmp/out" --quiet
expect_fail missing-path-file "nopath\.json" walk --path "$tmp/nopath.json" --out "$tmp/out" --quiet
expect_fail path-not-json "bad\.json" walk --path "$(path bad '{"frames": 10, ')" --out "$tmp/out" --quiet
expect_fail path-missing-keys "keys" walk --path "$(path nokeys '{"frames": 10}')" --out "$tmp/out" --quiet
expect_fail path-unknown-key "colour" walk --path "$(path unk "{$good, \"frames\": 10, \"colour\": 3}")" --out "$tmp/out" --quiet
expect_fail path-nan "near" walk --path "$(path nan "{$good, \"frames\": 10, \"near\": \"NaN\"}")" --out "$tmp/out" --quiet
expect_fail path-zero-frames "frames" walk --path "$(path zf "{$good, \"frames\": 0}")" --out "$tmp/out" --quiet
expect_fail path-keyframe-every-0 "keyframe_every" walk --path "$(path ke "{$good, \"frames\": 10, \"keyframe_every\": 0}")" --out "$tmp/out" --quiet
expect_fail path-near-ge-far "near|far" walk --path "$(path nf "{$good, \"frames\": 10, \"near\": 10, \"far\": 5}")" --out "$tmp/out" --quiet
expect_fail path-fov-0 "fov" walk --path "$(path f0 "{$good, \"frames\": 10, \"fov_y_deg\": 0}")" --out "$tmp/out" --quiet
expect_fail path-fov-180 "fov" walk --path "$(path f180 "{$good, \"frames\": 10, \"fov_y_deg\": 180}")" --out "$tmp/out" --quiet
expect_fail bad-tau "tau" walk --tau banana --out "$tmp/out" --quiet
expect_fail negative-tau "tau" walk --tau -5 --out "$tmp/out" --quiet
expect_fail negative-tau-gradient "tau-gradient.*-0.5" walk --tau-gradient -0.5 --out "$tmp/out" --quiet
expect_fail nan-tau-gradient "tau-gradient.*nan" walk --tau-gradient nan --out "$tmp/out" --quiet
expect_fail bad-criterion "criterion" walk --criterion nine-point --out "$tmp/out" --quiet
expect_fail bad-depth "depth" walk --depth float16 --out "$tmp/out" --quiet
expect_fail unknown-option "--warp-speed" walk --warp-speed 9 --out "$tmp/out" --quiet
expect_fail no-subcommand "subcommand" 
touch "$tmp/afile"
expect_fail out-is-a-file "afile" walk --out "$tmp/afile/sub" --frames 3 --quiet
HW_GL_FAIL=1 expect_fail no-gl-context "OSMesa|context" walk --frames 3 --out "$tmp/out" --quiet
expect_fail lod-frame-out-of-range "frame" lod --frame 100000 --out "$tmp/out/o.png"

echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
