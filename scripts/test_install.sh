#!/usr/bin/env bash
# The library as a user gets it: configured with -DBUILD_TESTING=OFF (so
# neither GoogleTest nor Google Benchmark is looked for), installed into a
# temporary prefix; examples/embed_headless and examples/embed_glfw built
# against the installed package with find_package(hybridwalk) and run (the
# GLFW one under Xvfb, its window read back and compared with the library's
# frame); the headless example built once more through pkg-config and
# against the Debian package `cpack -G DEB` makes; and docs/api.md checked
# to quote the headless example as it is.
set -euo pipefail
cd "$(dirname "$0")/.."
prefix=$(mktemp -d)
work=$(mktemp -d)
trap 'rm -rf "$prefix" "$work"' EXIT
# A consumer's configuration needs neither GoogleTest nor Google Benchmark
# (configured only: building it would compile the library a second time).
cmake -S . -B "$work/configure-only" -G Ninja -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF \
  >/dev/null
if grep -Eq '^(GTest_DIR|benchmark_DIR):PATH=/' "$work/configure-only/CMakeCache.txt"; then
  echo "test_install: BUILD_TESTING=OFF still looked for GoogleTest or Google Benchmark" >&2
  exit 1
fi
# The install rules are the same with the tests on: install the release
# build that test.sh made (HW_INSTALL_BUILD_DIR, default build/).
build=${HW_INSTALL_BUILD_DIR:-build}
cmake --build "$build" --target hybridwalk hybridwalk_library >/dev/null
cmake --install "$build" --prefix "$prefix" >/dev/null
for ex in embed_headless embed_glfw; do
  cmake -S "examples/$ex" -B "$work/$ex" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
  cmake --build "$work/$ex" >/dev/null
done
"$work/embed_headless/embed_headless" | tail -1
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" "$work/embed_glfw/embed_glfw" 30 "$work/window.ppm"
test -s "$work/window.ppm"
test -x "$prefix/bin/hybridwalk"
pcdir=$(dirname "$(find "$prefix" -name hybridwalk.pc)")
# The package config and the .pc name the headless backends this build has
# (as the installed program's `info` reports them), and no other.
built=$("$prefix/bin/hybridwalk" info | sed -n 's/^headless OpenGL backends built: //p')
config=$(find "$prefix" -name hybridwalkConfig.cmake)
requires=$(sed -n 's/^Requires: //p' "$pcdir/hybridwalk.pc")
for b in egl osmesa; do
  want=OFF
  grep -q "$b yes" <<<"$built" && want=ON
  grep -q "^set(hybridwalk_HAVE_${b^^} $want)" "$config" ||
    { echo "test_install: $config does not set hybridwalk_HAVE_${b^^} $want (built: $built)" >&2; exit 1; }
  case " $requires " in *" $b "*) got=ON ;; *) got=OFF ;; esac
  [ "$got" = "$want" ] ||
    { echo "test_install: hybridwalk.pc Requires '$requires' (built: $built)" >&2; exit 1; }
done
# shellcheck disable=SC2046
c++ -std=c++17 -O1 examples/embed_headless/main.cpp -o "$work/pc_headless" \
  $(PKG_CONFIG_PATH="$pcdir" pkg-config --cflags --libs hybridwalk)
"$work/pc_headless" >/dev/null
# The Debian package of the same install (cpack -G DEB), unpacked rather than
# installed: the headless example builds and runs against it too.
rm -f "$build"/hybridwalk_*.deb
(cd "$build" && cpack -G DEB >/dev/null)
dpkg-deb -x "$build"/hybridwalk_*.deb "$work/deb"
cmake -S examples/embed_headless -B "$work/deb_headless" -G Ninja \
  -DCMAKE_PREFIX_PATH="$work/deb/usr" >/dev/null
cmake --build "$work/deb_headless" >/dev/null
"$work/deb_headless/embed_headless" >/dev/null
python3 - <<'PY'
import sys
doc, src = open("docs/api.md").read(), open("examples/embed_headless/main.cpp").read()
sys.exit(0 if src in doc else "docs/api.md does not quote examples/embed_headless/main.cpp as it is")
PY
echo "test_install: installed package, both examples, pkg-config and the .deb: passed"
