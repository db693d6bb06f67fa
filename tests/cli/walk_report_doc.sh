#!/usr/bin/env bash
# docs/walk-report.md and report.json stay in step: two short walks (default,
# and async keyframes + frame budget + near objects); every key they write
# (top level, summary, per frame, per-frame ms, nested objects) must be a row
# of the doc's table for that object (<!-- table: PATH --> before it), and
# every row must be written by one of the walks unless the row (or its table)
# is marked "option-only". Usage: walk_report_doc.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
src=$2
doc="$src/docs/walk-report.md"
check "doc exists" test -s "$doc"
common=(--scene indoor:20k --frames 12 --strips 0 --quiet)
# Modes pinned: --mode auto's choice depends on the run's timings.
"$hw" walk "${common[@]}" --mode hybrid --out "$tmp/a" >"$tmp/a.out" 2>&1
rc=$?; check "default walk exits 0 ($(tail -2 "$tmp/a.out"))" test $rc -eq 0
# A budget large enough that a refresh always fits (no timing dependence),
# without pacing so the walk does not sleep it away.
"$hw" walk "${common[@]}" --mode hybrid --async-keyframes --frame-budget-ms 1000 --no-frame-pacing \
  --near 1 --out "$tmp/b" >"$tmp/b.out" 2>&1
rc=$?; check "async+budget+near walk exits 0 ($(tail -2 "$tmp/b.out"))" test $rc -eq 0
"$hw" walk --scene indoor:20k --frames 3 --strips 0 --quiet --mode geometry --out "$tmp/c" >"$tmp/c.out" 2>&1
rc=$?; check "geometry walk exits 0 ($(tail -2 "$tmp/c.out"))" test $rc -eq 0

cat >"$tmp/check.py" <<'PY'
import json, re, sys
mode, doc, reports = sys.argv[1], sys.argv[2], sys.argv[3:]
STATS = {"count", "min", "p5", "median", "p95", "max"}
written = {}  # object path ("summary", "frames[].ms", "stats", ...) -> keys seen

def walk(v, path):
    if isinstance(v, dict):
        p = "stats" if set(v) == STATS else path
        written.setdefault(p, set()).update(v)
        if p != "stats":
            for k, c in v.items():
                walk(c, k if path == "." else path + "." + k)
    elif isinstance(v, list):
        for c in v:
            walk(c, path + "[]")

for r in reports:
    with open(r) as f:
        walk(json.load(f), ".")

tables = {}  # path -> {key: option_only}
table_only = set()
current = None
for line in open(doc, encoding="utf-8"):
    m = re.match(r"\s*<!--\s*table:\s*(\S+)(\s+option-only)?\s*-->", line)
    if m:
        current = m.group(1)
        tables.setdefault(current, {})
        if m.group(2):
            table_only.add(current)
        continue
    if line.startswith("#"):
        current = None
        continue
    m = re.match(r"\|\s*`([^`]+)`\s*\|", line)
    if current and m:
        tables[current][m.group(1)] = "(option-only" in line or current in table_only

problems = []
if mode == "written-in-doc":
    for path in sorted(written):
        if path not in tables:
            problems.append("no table for %s (keys: %s)" % (path, ", ".join(sorted(written[path]))))
            continue
        for k in sorted(written[path] - set(tables[path])):
            problems.append("%s: `%s` written but not documented" % (path, k))
elif mode == "doc-in-written":
    for path in sorted(tables):
        for k, opt in sorted(tables[path].items()):
            if not opt and k not in written.get(path, set()):
                problems.append("%s: `%s` documented but written by neither walk "
                                "(removed? or mark the row (option-only))" % (path, k))
elif mode == "count":
    n = sum(len(t) for t in tables.values())
    print("%d keys documented in %d tables; %d written keys in %d objects" % (
        n, len(tables), sum(len(s) for s in written.values()), len(written)))
for p in problems:
    print("  " + p)
sys.exit(1 if problems else 0)
PY
reports=("$tmp/a/report.json" "$tmp/b/report.json" "$tmp/c/report.json")
check "report.json written twice" test -s "$tmp/a/report.json" -a -s "$tmp/b/report.json"
check "every written key is documented" python3 "$tmp/check.py" written-in-doc "$doc" "${reports[@]}"
check "every documented key is written" python3 "$tmp/check.py" doc-in-written "$doc" "${reports[@]}"
python3 "$tmp/check.py" count "$doc" "${reports[@]}"
finish
