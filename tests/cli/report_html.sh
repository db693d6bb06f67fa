#!/usr/bin/env bash
# The sweep's index.html renders in a real browser (Debian's chromium,
# headless) with its images: the screenshot is kept as a test artifact in
# build/artifacts/sweep_index.png. Usage: report_html.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
artifacts=$(dirname "$(dirname "$hw")")/artifacts
mkdir -p "$artifacts"
"$hw" sweep --scene indoor:20k --frames 11 --tau 2^11,2^15 --five-point-only --no-variants \
  --out "$tmp/s" --quiet >"$tmp/out" 2>&1
rc=$?; check "sweep exits 0" test $rc -eq 0
check "chromium is installed (scripts/setup.sh)" command -v chromium
shot="$artifacts/sweep_index.png"
rm -f "$shot"
timeout 120 chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
  --disable-background-networking --disable-component-update --disable-sync \
  --user-data-dir="$tmp/profile" --hide-scrollbars --window-size=1400,3200 \
  --screenshot="$shot" "file://$tmp/s/index.html" >"$tmp/chromium.log" 2>&1
check "chromium took a screenshot ($(tail -1 "$tmp/chromium.log"))" test -s "$shot"
# The page draws its images: compare with the same page whose PNGs were
# removed (broken images draw nothing); the real one must be clearly richer
# (the window tall enough for the overlays below the wider Pareto plot).
cp -r "$tmp/s" "$tmp/noimg"
find "$tmp/noimg" -name '*.png' -delete
timeout 120 chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
  --disable-background-networking --disable-component-update --disable-sync \
  --user-data-dir="$tmp/profile2" --hide-scrollbars --window-size=1400,3200 \
  --screenshot="$tmp/noimg.png" "file://$tmp/noimg/index.html" >/dev/null 2>&1
size=$(stat -c %s "$shot" 2>/dev/null || echo 0)
size0=$(stat -c %s "$tmp/noimg.png" 2>/dev/null || echo 0)
check "screenshot shows the images (${size} bytes vs ${size0} without them)" \
  test "$size0" -gt 0 -a "$size" -gt $((size0 * 6 / 5))
check "index.html references existing images" \
  bash -c 'cd "$1" && for f in $(grep -o "src=\"[^\"]*\"" index.html | sed "s/src=\"//; s/\"$//"); do test -s "$f" || { echo "missing $f"; exit 1; }; done' _ "$tmp/s"
finish
