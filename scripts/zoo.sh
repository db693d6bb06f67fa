#!/usr/bin/env bash
# Scene zoo: every OpenArena map, TORCS track and MORSE environment in the
# scene cache walked from its default path, one row each: triangles, load s,
# in-between PSNR median / p5, frame ms / geometry ms, the first frame's
# sky/void fraction and whether its eye stands in playable space (a floor
# within 3 m below, no surface within 0.1 m); a failure keeps its reason.
# Writes OUT/zoo.csv, OUT/zoo.md and OUT/contact_sheet.png (first frames).
#
# Usage: scripts/zoo.sh [--hw BIN] [--out DIR] [--frames N] [--resolution WxH]
#                       [--only SPEC,SPEC,...] [--kinds q3,torcs,morse]
set -u
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
hw="$here/build/bin/hybridwalk"
out="$here/out/zoo"
frames=40
res=256x256
only=""
kinds="q3,torcs,morse"
while [ $# -gt 0 ]; do
  case $1 in
    --hw) hw=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --resolution) res=$2; shift 2 ;;
    --only) only=$2; shift 2 ;;
    --kinds) kinds=$2; shift 2 ;;
    *) echo "zoo.sh: unknown option '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
mkdir -p "$out/runs" || exit 1

if [ -n "$only" ]; then
  specs=$(echo "$only" | tr ',' '\n')
else
  specs=$("$hw" scenes list | awk -v k=",$kinds," 'index(k, "," $1 ",") && $3 != "NOT" { print $2 }')
fi
[ -n "$specs" ] || { echo "zoo.sh: no scenes (run 'hybridwalk scenes fetch --outdoor')" >&2; exit 1; }

csv="$out/zoo.csv"
echo "spec,triangles,load_s,psnr_median,psnr_p5,frame_ms,geometry_ms,empty_fraction,floor_drop,clearance,eye_ok,status,reason" >"$csv"
for spec in $specs; do
  d="$out/runs/$(echo "$spec" | tr ':/' '__')"
  rm -rf "$d"; mkdir -p "$d"
  echo "zoo: $spec" >&2
  "$hw" render --scene "$spec" --width "${res%x*}" --height "${res#*x}" --frames 1 --quiet --out "$d/render" \
    >"$d/render.out" 2>"$d/render.err"
  rrc=$?
  wrc=1
  if [ $rrc -eq 0 ]; then
    "$hw" walk --scene "$spec" --width "${res%x*}" --height "${res#*x}" --frames "$frames" --strips 1 --quiet \
      --out "$d/walk" >"$d/walk.out" 2>"$d/walk.err"
    wrc=$?
  fi
  python3 - "$spec" "$d" "$rrc" "$wrc" >>"$csv" <<'EOF'
import csv, json, re, sys
spec, d, rrc, wrc = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
row = dict(spec=spec)
def last_error(f):
    try:
        lines = [l.strip() for l in open(f, errors="replace") if "error" in l.lower()]
        return lines[-1] if lines else "exit status non-zero"
    except OSError:
        return "no output"
try:
    err = open(d + "/render.err", errors="replace").read()
    m = re.search(r"scene \S+: (\d+) triangles, \d+ meshes, loaded in ([0-9.]+) ms", err)
    if m:
        row["triangles"] = m.group(1)
        row["load_s"] = "%.2f" % (float(m.group(2)) / 1000)
except OSError:
    pass
status, reason = "ok", ""
if rrc >= 128:
    status, reason = "FAIL", "render crashed (signal %d) while loading the scene" % (rrc - 128)
elif rrc != 0:
    status, reason = "FAIL", "render: " + last_error(d + "/render.err")
else:
    f = json.load(open(d + "/render/render.json"))["summary"]["first_frame"]
    open_ = f["sky_or_void_fraction"]
    row["empty_fraction"] = "%.3f" % open_
    row["floor_drop"] = "" if f["floor_drop"] is None else "%.2f" % f["floor_drop"]
    row["clearance"] = "%.2f" % f["clearance"]
    eye_ok = f["floor_drop"] is not None and f["floor_drop"] <= 3.0 and f["clearance"] >= 0.1
    row["eye_ok"] = "yes" if eye_ok else "no"
    why = []
    if f["floor_drop"] is None: why.append("no floor below the first eye")
    elif f["floor_drop"] > 3.0: why.append("first eye %.1f m above the floor" % f["floor_drop"])
    if f["clearance"] < 0.1: why.append("first eye %.2f m from a surface (inside a wall?)" % f["clearance"])
    if open_ >= 0.5: why.append("first frame %.0f %% sky/void" % (100 * open_))
    if wrc != 0:
        why.append("walk: " + last_error(d + "/walk.err"))
    else:
        s = json.load(open(d + "/walk/report.json"))["summary"]
        num = lambda v: "" if v is None else "%.2f" % v
        row["psnr_median"] = num(s["psnr"]["median"])
        row["psnr_p5"] = num(s["psnr"]["p5"])
        row["frame_ms"] = num(s["frame_ms"]["median"])
        row["geometry_ms"] = num(s["reference_ms"]["median"])
    if why:
        status, reason = "FAIL", "; ".join(why)
row["status"], row["reason"] = status, reason
cols = "spec,triangles,load_s,psnr_median,psnr_p5,frame_ms,geometry_ms,empty_fraction,floor_drop,clearance,eye_ok,status,reason".split(",")
csv.writer(sys.stdout).writerow([row.get(c, "") for c in cols])
EOF
done

python3 - "$csv" "$out/zoo.md" "$frames" "$res" <<'EOF'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
out = open(sys.argv[2], "w")
kinds = {}
for r in rows:
    k = r["spec"].split(":")[0]
    kinds.setdefault(k, [0, 0])
    kinds[k][0] += 1
    kinds[k][1] += r["status"] == "ok"
out.write("# Scene zoo: every scene from its default path (%s, %s frames)\n\n" % (sys.argv[4], sys.argv[3]))
out.write("Pass: the walk runs, the first eye has a floor within 3 m below it and no surface within 0.1 m, and the first frame is less than half sky/void (64 x 64 rays through the first camera that hit no surface other than sky within the far plane).\n\n")
for k, (n, ok) in kinds.items():
    out.write("- %s: %d of %d pass\n" % (k, ok, n))
out.write("\nContact sheet (contact_sheet.png): the first frames in the table's order, 8 per row.\n")
out.write("\n| scene | triangles | load s | PSNR median / p5 dB | frame / geometry ms | sky/void | floor drop m | eye ok | status |\n")
out.write("|---|---:|---:|---:|---:|---:|---:|---|---|\n")
for r in rows:
    st = r["status"] if r["status"] == "ok" else "**FAIL**: " + r["reason"].replace("|", "/")
    out.write("| %s | %s | %s | %s / %s | %s / %s | %s | %s | %s | %s |\n" % (
        r["spec"], r["triangles"], r["load_s"], r["psnr_median"], r["psnr_p5"], r["frame_ms"],
        r["geometry_ms"], r["empty_fraction"], r["floor_drop"], r["eye_ok"], st))
EOF

# Contact sheet: first frames, 8 per row in the table's order (a crossed
# grey tile where a scene has no first frame).
imgs=()
for spec in $specs; do
  f="$out/runs/$(echo "$spec" | tr ':/' '__')/render/0000.png"
  [ -f "$f" ] && imgs+=("$f") || imgs+=(-)
done
python3 "$here/scripts/contact_sheet.py" "$out/contact_sheet.png" 8 128 "${imgs[@]}"
fails=$(grep -c ',FAIL,' "$csv")
echo "zoo: $(($(wc -l <"$csv") - 1)) scenes, $fails failed; $out/zoo.md" >&2
[ "$fails" -eq 0 ]
