#!/usr/bin/env bash
# The walk's index.html loads in a real browser (Debian's chromium, headless)
# with no console message (the page has no scripts: any message is an error)
# and every image drawn; `hybridwalk report DIR` rebuilds the same page from
# report.json. The screenshot is kept in build/artifacts/walk_index.png.
# Usage: walk_page_html.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
artifacts=$(dirname "$(dirname "$hw")")/artifacts
mkdir -p "$artifacts"
"$hw" walk --scene indoor:20k --mode hybrid --width 160 --height 120 --frames 21 --strips 2 \
  --out "$tmp/w" --quiet >"$tmp/out" 2>&1
rc=$?; check "walk exits 0" test $rc -eq 0
for f in index.html psnr_along_path.png frame_times.png report.json; do
  check "walk wrote $f" test -s "$tmp/w/$f"
done
check "chromium is installed (scripts/setup.sh)" command -v chromium
browse() {  # browse PAGE LOG [SCREENSHOT]: load PAGE headless, console to LOG
  local extra=(--dump-dom)
  [ $# -ge 3 ] && extra=(--hide-scrollbars --window-size=1400,2600 --screenshot="$3")
  timeout 120 chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
    --disable-background-networking --disable-component-update --disable-sync \
    --user-data-dir="$tmp/profile$RANDOM" --enable-logging=stderr --log-level=0 \
    --virtual-time-budget=5000 "${extra[@]}" "file://$1" >/dev/null 2>"$2"
}
shot="$artifacts/walk_index.png"
rm -f "$shot"
browse "$tmp/w/index.html" "$tmp/page.log" "$shot"
check "chromium took a screenshot" test -s "$shot"
check "no console message ($(grep -m1 CONSOLE "$tmp/page.log"))" bash -c '! grep -q ":CONSOLE" "$1"' _ "$tmp/page.log"
# Every image loads: the same page with a probe that reports each image.
probe='<script>addEventListener("load", () => { const im = [...document.images];
 const bad = im.filter(i => !(i.complete && i.naturalWidth > 0)).map(i => i.src);
 if (bad.length) console.error("broken images: " + bad.join(" "));
 else console.log("images loaded: " + im.length); });</script>'
{ cat "$tmp/w/index.html"; echo "$probe"; } >"$tmp/w/probe.html"  # a script after </html> still runs
browse "$tmp/w/probe.html" "$tmp/probe.log"
n=$(sed -n 's/.*"images loaded: \([0-9]*\)".*/\1/p' "$tmp/probe.log")
check "every image loads (${n:-none} images; $(grep -m1 -o 'broken images[^"]*' "$tmp/probe.log"))" test "${n:-0}" -ge 4
# The probe sees a missing image (so the check above can fail).
cp -r "$tmp/w" "$tmp/broken"
rm "$tmp/broken/psnr_along_path.png"
browse "$tmp/broken/probe.html" "$tmp/broken.log"
check "the probe reports a missing image" grep -q "broken images: .*psnr_along_path.png" "$tmp/broken.log"
# `report DIR` rebuilds the page from report.json alone.
cp "$tmp/w/index.html" "$tmp/first.html"
rm "$tmp/w/index.html" "$tmp/w/psnr_along_path.png"
"$hw" report "$tmp/w" >"$tmp/report.out" 2>&1
rc=$?; check "report exits 0" test $rc -eq 0
check "report rebuilt the same page" cmp -s "$tmp/first.html" "$tmp/w/index.html"
check "report rebuilt the PSNR plot" test -s "$tmp/w/psnr_along_path.png"
check "report prints the walk's summary line" grep -qE '^indoor:20k, 21 frames: [0-9]+ % warped' "$tmp/report.out"
"$hw" report "$tmp/nowhere" >"$tmp/bad.out" 2>&1
rc=$?; check "report of a folder without report.json exits 1" test $rc -eq 1
check "  and names the file" grep -q "nowhere/report.json" "$tmp/bad.out"
finish
