#!/usr/bin/env bash
# Small real runs of `sweep` and `bench`: outputs exist, tables have the
# expected rows, plots are PNGs, and bad options are refused.
# Usage: sweep_bench.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
is_png() { [ "$(head -c 8 "$1" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ]; }

"$hw" sweep --scene indoor:20k --frames 11 --tau 2^8,2^11,2^15 --out "$tmp/s" --quiet >"$tmp/out" 2>&1
rc=$?; check "sweep exits 0 ($(tail -2 "$tmp/out"))" test $rc -eq 0
check "sweep.json" test -s "$tmp/s/sweep.json"
# 3 taus x (2 criteria + 3 variants) + tile baselines (1..3, deduplicated) + per-pixel.
rows=$(($(wc -l <"$tmp/s/sweep.csv") - 1))
check "sweep.csv has 17..19 rows (got $rows)" test "$rows" -ge 17 -a "$rows" -le 19
check "five-point rows" test "$(grep -c ',five-point,' "$tmp/s/sweep.csv")" -eq 12
check "region-local rows" test "$(grep -c ',region-local,' "$tmp/s/sweep.csv")" -eq 3
check "merge rows" test "$(grep -c '+merge,' "$tmp/s/sweep.csv")" -eq 6
check "per-axis rows" test "$(grep -c ',per-axis-max,' "$tmp/s/sweep.csv")" -eq 3
check "per-pixel row" grep -q '^per-pixel,' "$tmp/s/sweep.csv"
check "uniform tile rows" grep -q '^uniform-tiles,' "$tmp/s/sweep.csv"
for p in pareto quads_vs_tau psnr_vs_tau; do check "$p.png" is_png "$tmp/s/$p.png"; done
check "3 overlays" test "$(ls "$tmp/s/overlays" | wc -l)" -eq 3
check "index.html links the plot" grep -q 'pareto.png' "$tmp/s/index.html"

"$hw" bench --quick --sizes 20k,40k --quiet --out "$tmp/b" >"$tmp/bout" 2>&1
rc=$?; check "bench exits 0 ($(tail -2 "$tmp/bout"))" test $rc -eq 0
check "bench.json" grep -q '"complexity"' "$tmp/b/bench.json"
check "per-scene table: both quick scenes, default and paper, with frame/geometry ratios" python3 -c "
import json,sys
rows = json.load(open('$tmp/b/scenes.json'))['rows']
ok = [r['scene'] for r in rows] == ['indoor:100k', 'outdoor:100k'] and all(
    r[p]['frames'] == 41 and r[p]['frame_over_reference_median'] > 0 and
    abs(r[p]['geometry_share'] + r[p]['warp_share'] + r[p]['keyframe_share'] - 1) < 1e-9 and
    r['paper']['geometry_share'] == 0 for r in rows for p in ('default', 'paper'))
sys.exit(0 if ok else 1)"
check "scenes.md and scenes.csv" test -s "$tmp/b/scenes.md" -a -s "$tmp/b/scenes.csv"
# The paper row of indoor warps every in-between frame: its shares in
# scenes.md are percentages adding up to 100 (each rounded).
check "scenes.md shows shares in percent" python3 -c "
import re,sys
row = [l for l in open('$tmp/b/scenes.md') if l.startswith('| indoor:100k |') and '| paper |' in l][0]
g, w, k = (int(x) for x in re.search(r'\| (\d+)% / (\d+)% / (\d+)% \|', row).groups())
sys.exit(0 if g == 0 and w >= 70 and 99 <= g + w + k <= 101 else 1)"
for p in complexity trace spacing; do check "$p.png" is_png "$tmp/b/$p.png"; done
check "complexity.csv rows" test "$(($(wc -l <"$tmp/b/complexity.csv") - 1))" -eq 8
check "index.html" grep -q 'Keyframe spacing' "$tmp/b/index.html"
# (d) the skip table: 5 skips + 3 subdivision modes on indoor; the lossless ones leave PSNR unchanged,
# the sky, near-object and subdivision rows are the only ones allowed to change it.
check "skips.csv has 8 rows" test "$(($(wc -l <"$tmp/b/skips.csv") - 1))" -eq 8
check "lossless skips keep PSNR" awk -F, 'NR > 1 && $3 ~ /fused|background|previous/ && $11 != $12 { bad = 1 } END { exit bad }' "$tmp/b/skips.csv"
check "index.html has the skip table" grep -q 'Skips' "$tmp/b/index.html"
# Subdivision rows: uniform cuts leaves, none does not; both measure the
# large-quad pixels (PSNR column 15, pixel share column 19).
check "subdivision uniform cuts leaves" awk -F, '$3 == "subdivision uniform" && $23 > 0 { ok = 1 } END { exit !ok }' "$tmp/b/skips.csv"
check "subdivision none cuts none" awk -F, '$3 == "subdivision none" && $23 == 0 { ok = 1 } END { exit !ok }' "$tmp/b/skips.csv"
check "large-quad PSNR measured" awk -F, '$3 ~ /^subdivision/ && ($15 == "-" || $19 <= 0) { bad = 1 } END { exit bad }' "$tmp/b/skips.csv"
"$hw" bench --only skips,nonsense --out "$tmp/bad3" >/dev/null 2>"$tmp/err"
check "bench --only unknown part refused" test $? -eq 2

"$hw" sweep --tau 2^x --out "$tmp/bad" --quiet >/dev/null 2>"$tmp/err"
check "sweep bad tau refused" test $? -ne 0
check "sweep bad tau message" grep -q "tau" "$tmp/err"
check "sweep bad tau wrote nothing" test ! -e "$tmp/bad"
"$hw" bench --sizes 10 --out "$tmp/bad2" >/dev/null 2>"$tmp/err"
check "bench bad sizes refused" test $? -ne 0
check "bench bad sizes message" grep -q "sizes" "$tmp/err"

finish
