#!/usr/bin/env bash
# Runs one row of the bad-input catalogue (tests/catalogue/cases.tsv,
# docs/bad-input.md): writes the malformed fixtures into a fresh temp dir,
# runs the row's command under a timeout and checks that
#   - the exit status is the row's (1 = runtime error, 2 = usage error;
#     `1|2` where either would do):
#     never 0, never >= 128 (a signal, i.e. a crash), never 124 (a hang);
#   - stderr matches the row's regex (case-insensitive ERE), which names
#     what is wrong and where (file, key, option);
#   - the output dir {out} is left clean: for `empty` rows it does not exist
#     or holds nothing (not even an empty folder); for `no-partial` rows (the
#     failure comes after work started) it holds no *.tmp-* file and no
#     report.json/render.json that would make a partial run look complete;
#     for `untouched` rows it is byte for byte what the setup left (names,
#     kinds, sizes, contents: the refused run changed nothing).
# Setups: `-`; `tmpfs:SIZE` / `tmpfs-ro` mounted at {out}; `foreign` ({out}
# holds a user's files: thesis.tmp-999999, notes.txt); `pre:CMD` (CMD, with
# the placeholders, run from the fixture dir first; it must exit 0).
# Usage: run_case.sh ID HYBRIDWALK SOURCE_DIR     (ID `all` runs every row)
set -u
id=${1:?usage: run_case.sh ID HYBRIDWALK SOURCE_DIR}
hw=${2:?usage: run_case.sh ID HYBRIDWALK SOURCE_DIR}
src=${3:?usage: run_case.sh ID HYBRIDWALK SOURCE_DIR}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
cases="$here/cases.tsv"
timeout_s=${HW_CATALOGUE_TIMEOUT:-120}

if [ "$id" = all ]; then
  failed=0 n=0
  for i in $(awk -F'\t' '/^[a-z]/ { print $1 }' "$cases"); do
    n=$((n + 1))
    if out=$(bash "${BASH_SOURCE[0]}" "$i" "$hw" "$src" 2>&1); then
      echo "ok   $i"
    else
      echo "FAIL $i"; echo "$out" | sed 's/^/     /'; failed=$((failed + 1))
    fi
  done
  echo "$((n - failed)) of $n rows pass"
  [ $failed -eq 0 ]
  exit
fi

row=$(awk -F'\t' -v id="$id" '$1 == id' "$cases")
[ -n "$row" ] || { echo "run_case.sh: no row '$id' in $cases"; exit 1; }
IFS=$'\t' read -r _ want_exit clean setup description command regex <<<"$row"

# Rows that need a tiny or read-only filesystem at {out} mount a tmpfs there.
# Root can do that directly; anyone else gets a private mount namespace in
# which they are root (unshare -rm), so the mount never leaks out.
if [[ $setup == tmpfs* ]] && [ "$(id -u)" != 0 ] && [ -z "${HW_CATALOGUE_USERNS:-}" ]; then
  if unshare --map-root-user --mount true 2>/dev/null; then
    HW_CATALOGUE_USERNS=1 exec unshare --map-root-user --mount bash "${BASH_SOURCE[0]}" "$@"
  fi
  echo "FAIL $id: needs a tmpfs mount ($setup) but this user is not root and" \
    "'unshare --map-root-user --mount' is not allowed here"
  exit 1
fi

tmp=$(mktemp -d "${TMPDIR:-/tmp}/hw-catalogue.XXXXXX")
out="$tmp/out"
cleanup() {
  mountpoint -q "$out" 2>/dev/null && umount "$out"
  rm -rf "$tmp"
}
trap cleanup EXIT

# ---------------------------------------------------------------- fixtures --
# Scene files. Deterministic: no /dev/urandom, so a failure reproduces.
: >"$tmp/empty.obj"
printf 'v 0 0 0\nv 1 0\nf 1 2 3 4 5\n' >"$tmp/trunc.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2' >"$tmp/trunc_mid.obj"
awk 'BEGIN { srand(7); for (i = 0; i < 4000; i++) printf "%c", 1 + int(rand() * 254) }' \
  >"$tmp/garbage.obj"
printf 'hello' >"$tmp/scene.xyz123"
mkdir "$tmp/dir.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n' >"$tmp/face_oob.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -7\n' >"$tmp/face_neg.obj"
printf 'v nan 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 3 4\n' >"$tmp/nan_vertex.obj"
printf 'ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' \
  >"$tmp/huge_vertex_count.ply"
{
  printf 'ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 2000000000\nproperty list uchar int vertex_indices\nend_header\n'
  printf '\0\0\0\0\0\0\0\0\0\0\0\0\0\0\x80\x3f\0\0\0\0\0\0\0\0\0\0\0\0\0\0\x80\x3f\0\0\0\0'
  printf '\3\0\0\0\0\1\0\0\0\2\0\0\0'
} >"$tmp/huge_face_count.ply"
printf 'PK\3\4 this is not a PLY file at all\n' >"$tmp/not_ply.ply"
printf '{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {"POSITION": 7}}]}]' \
  >"$tmp/broken.gltf"

# pk3/BSP: each folder is one $HYBRIDWALK_PK3_DIR; the scene cache
# ($HYBRIDWALK_CACHE) is an empty folder so only the broken pk3 is seen.
mkdir -p "$tmp/cache" "$tmp/pk3_garbage" "$tmp/pk3_trunc" "$tmp/pk3_other" \
  "$tmp/pk3_badmagic" "$tmp/pk3_badlump" "$tmp/pk3_deflate"
head -c 5000 "$tmp/garbage.obj" >"$tmp/pk3_garbage/broken.pk3"
python3 - "$tmp" <<'EOF' || { echo "FAIL $id: python3 is needed to write the pk3 fixtures"; exit 1; }
import struct, sys, zipfile, zlib
t = sys.argv[1]
def pk3(path, name, data, method=zipfile.ZIP_STORED):
    with zipfile.ZipFile(path, 'w', method) as z:
        z.writestr(name, data)
# A BSP header whose lumps all point past the end of the file.
bad_lumps = b'IBSP' + struct.pack('<i', 46) + b''.join(
    struct.pack('<ii', 1000000 * (i + 1), 50000) for i in range(17))
pk3(t + '/pk3_other/maps.pk3', 'maps/other.bsp', bad_lumps)
pk3(t + '/pk3_badmagic/maps.pk3', 'maps/bad.bsp', b'garbage' * 100)
pk3(t + '/pk3_badlump/maps.pk3', 'maps/bad.bsp', bad_lumps)
# Truncated download: a zip cut in half (its central directory is lost).
pk3(t + '/whole.pk3', 'maps/cut.bsp', bad_lumps + bytes(range(256)) * 40)
whole = open(t + '/whole.pk3', 'rb').read()
open(t + '/pk3_trunc/cut.pk3', 'wb').write(whole[: len(whole) // 2])
# Intact zip directory, damaged deflate stream inside the member.
pk3(t + '/pk3_deflate/maps.pk3', 'maps/crc.bsp', bad_lumps + b'x' * 5000, zipfile.ZIP_DEFLATED)
d = bytearray(open(t + '/pk3_deflate/maps.pk3', 'rb').read())
for i in range(60, 90):
    d[i] ^= 0xFF
open(t + '/pk3_deflate/maps.pk3', 'wb').write(bytes(d))
EOF

# Camera paths: a valid base with one thing wrong each.
keys='"keys": [{"eye": [0, 1.7, 0], "look_at": [0, 1.7, -5]}, {"eye": [1, 1.7, -1], "look_at": [1, 1.7, -6]}]'
pj() { printf '%s' "$2" >"$tmp/$1.json"; }
pj path_not_json '{"frames": 10, '
: >"$tmp/path_empty.json"
mkdir "$tmp/path_dir.json"
pj path_top_array '[1, 2, 3]'
pj path_no_keys '{"frames": 10}'
pj path_unknown_key "{$keys, \"frames\": 10, \"colour\": 3}"
pj path_wrong_type "{$keys, \"frames\": \"ten\"}"
pj path_keys_object '{"keys": {"eye": [0, 1.7, 0], "look_at": [0, 1.7, -5]}, "frames": 10}'
pj path_nan_string "{$keys, \"frames\": 10, \"near\": \"NaN\"}"
pj path_inf_string "{$keys, \"frames\": 10, \"far\": \"Infinity\"}"
pj path_inf_bare "{$keys, \"frames\": 10, \"far\": Infinity}"
pj path_neg_frames "{$keys, \"frames\": -5}"
pj path_zero_frames "{$keys, \"frames\": 0}"
pj path_frac_frames "{$keys, \"frames\": 2.5}"
pj path_huge_frames "{$keys, \"frames\": 99999999999}"
pj path_ke_zero "{$keys, \"frames\": 10, \"keyframe_every\": 0}"
pj path_near_zero "{$keys, \"frames\": 10, \"near\": 0}"
pj path_near_neg "{$keys, \"frames\": 10, \"near\": -1}"
pj path_near_ge_far "{$keys, \"frames\": 10, \"near\": 10, \"far\": 5}"
pj path_fov_0 "{$keys, \"frames\": 10, \"fov_y_deg\": 0}"
pj path_fov_180 "{$keys, \"frames\": 10, \"fov_y_deg\": 180}"
pj path_fov_neg "{$keys, \"frames\": 10, \"fov_y_deg\": -5}"
pj path_width_0 "{$keys, \"frames\": 10, \"width\": 0}"
pj path_width_huge "{$keys, \"frames\": 10, \"width\": 100000}"
pj path_up_zero "{$keys, \"frames\": 10, \"up\": [0, 0, 0]}"
pj path_eye_is_look_at '{"keys": [{"eye": [0, 1.7, 0], "look_at": [0, 1.7, 0]}], "frames": 10}'
pj path_view_parallel_up '{"keys": [{"eye": [0, 1.7, 0], "look_at": [0, 5, 0]}], "frames": 10}'
pj path_empty_keys '{"keys": [], "frames": 10}'
pj path_eye_2d '{"keys": [{"eye": [0, 1.7], "look_at": [0, 1.7, -5]}], "frames": 10}'
pj path_key_no_look_at '{"keys": [{"eye": [0, 1.7, 0]}], "frames": 10}'
pj path_key_unknown '{"keys": [{"eye": [0, 1.7, 0], "look_at": [0, 1.7, -5], "roll": 30}], "frames": 10}'
pj path_trailing "{$keys, \"frames\": 10} trailing"
# 10 MiB of nested arrays: [[[[...]]]] 5 Mi deep. Only written when used.
if [[ $command == *path_nested.json* ]]; then
  awk 'BEGIN { n = 5 * 1024 * 1024; s = "["; while (length(s) < n) s = s s;
               s = substr(s, 1, n); t = s; gsub(/\[/, "]", t); printf "%s%s", s, t }' \
    >"$tmp/path_nested.json"
fi

# TORCS tracks (tracks/CATEGORY/NAME/NAME.acc + NAME.xml): a small model
# (one quad) and track descriptions with one thing wrong each.
acc_quad='AC3Db\nMATERIAL "m" rgb 0.5 0.5 0.5  amb 0.2 0.2 0.2  emis 0 0 0  spec 0 0 0  shi 0  trans 0\nOBJECT world\nkids 1\nOBJECT poly\nname "ground"\nnumvert 4\n0 0 0\n500 0 0\n500 0 -500\n0 0 -500\nnumsurf 1\nSURF 0x10\nmat 0\nrefs 4\n0 0 0\n1 1 0\n2 1 1\n3 0 1\nkids 0\n'
torcs_seg() { printf '<section name="%s"><attstr name="type" val="%s"/>%s</section>\n' "$@"; }
torcs_xml() {  # NAME SEGMENTS...: tracks/road/NAME/NAME.{acc,xml}
  local n=$1; shift
  mkdir -p "$tmp/tracks/road/$n"
  printf "$acc_quad" >"$tmp/tracks/road/$n/$n.acc"
  { printf '<?xml version="1.0"?>\n<params name="%s" type="trackdef">\n<section name="Main Track">\n<attnum name="width" unit="m" val="10"/>\n<section name="Track Segments">\n' "$n"
    printf '%s' "$@"
    printf '</section>\n</section>\n</params>\n'; } >"$tmp/tracks/road/$n/$n.xml"
}
str200=$(torcs_seg front str '<attnum name="lg" unit="m" val="200"/>')
turn=$(torcs_seg turn lft '<attnum name="radius" unit="m" val="50"/><attnum name="arc" unit="deg" val="180"/>')
torcs_xml oval "$str200" "$turn" "$(torcs_seg back str '<attnum name="lg" unit="m" val="200"/>')" \
  "$(torcs_seg 'last turn' lft '<attnum name="radius" unit="m" val="50"/><attnum name="arc" unit="deg" val="180"/>')"
torcs_xml open "$str200" "$turn" "$(torcs_seg back str '<attnum name="lg" unit="m" val="150"/>')" \
  "$(torcs_seg 'last turn' lft '<attnum name="radius" unit="m" val="50"/><attnum name="arc" unit="deg" val="180"/>')"
torcs_xml zig "$str200" "$(torcs_seg wiggle zig '')"
torcs_xml nolen "$(torcs_seg front str '')"
torcs_xml badnum "$(torcs_seg front str '<attnum name="lg" unit="m" val="2OO"/>')"
torcs_xml cut "$str200"
head -c 120 "$tmp/tracks/road/cut/cut.xml" >"$tmp/cut.xml" && mv "$tmp/cut.xml" "$tmp/tracks/road/cut/cut.xml"
mkdir -p "$tmp/tracks/road/nodesc" && printf "$acc_quad" >"$tmp/tracks/road/nodesc/nodesc.acc"

touch "$tmp/a_file"

# Hostile input (docs/bad-input.md "Hostile input"): special files where a
# regular file is expected, declared sizes far beyond the bytes present,
# nesting, duplicate keys, references out of the model's folder.
mkfifo "$tmp/fifo.json" "$tmp/fifo.png" "$tmp/fifo.obj" "$tmp/fifo_out"
ln -s /dev/null "$tmp/null.png"
ln -s /dev/null "$tmp/null_dir"
ln -s /dev/zero "$tmp/zero.json"
ln -s /dev/zero "$tmp/zero.obj"
truncate -s 100M "$tmp/huge_path.json"  # sparse: 100 MiB of zero bytes
pj path_width_5 "{$keys, \"frames\": 10, \"width\": 5}"
pj path_height_1 "{$keys, \"frames\": 10, \"height\": 1}"
pj path_eye_huge '{"keys": [{"eye": [1e308, 1.7, 0], "look_at": [0, 1.7, -5]}], "frames": 10}'
pj path_look_at_huge '{"keys": [{"eye": [0, 1.7, 0], "look_at": [0, 1.7, -1e308]}], "frames": 10}'
pj path_up_huge "{$keys, \"frames\": 10, \"up\": [1e308, 1e308, 0]}"
pj path_frames_intmax "{$keys, \"frames\": 2147483647}"
pj path_near_subnormal "{$keys, \"frames\": 10, \"near\": 5e-324}"
pj path_fov_tiny "{$keys, \"frames\": 10, \"fov_y_deg\": 1e-300}"
pj path_far_over_near "{$keys, \"frames\": 10, \"near\": 0.00001, \"far\": 100000}"
pj path_far_huge "{$keys, \"frames\": 10, \"far\": 1e300}"
pj path_dup_frames "{$keys, \"frames\": 10, \"frames\": 20}"
pj path_dup_eye '{"keys": [{"eye": [0, 1.7, 0], "eye": [9, 1.7, 0], "look_at": [0, 1.7, -5]}], "frames": 10}'
pj path_small_64 '{"width": 64, "height": 64, "keys": [{"eye": [0, 1.7, 0], "look_at": [0, 1.7, -5]}, {"eye": [1, 1.7, -1], "look_at": [1, 1.7, -6]}], "frames": 3}'
pj path_small_96 '{"width": 96, "height": 96, "keys": [{"eye": [0, 1.7, 0], "look_at": [0, 1.7, -5]}, {"eye": [1, 1.7, -1], "look_at": [1, 1.7, -6]}], "frames": 3}'
pj path_small_64_moved '{"width": 64, "height": 64, "keys": [{"eye": [0.5, 1.7, 0], "look_at": [0.5, 1.7, -5]}, {"eye": [1.5, 1.7, -1], "look_at": [1.5, 1.7, -6]}], "frames": 3}'
awk 'BEGIN { n = 200; s = ""; for (i = 0; i < n; i++) s = s "["; t = s; gsub(/\[/, "]", t);
             printf "{\"keys\": %s%s, \"frames\": 3}", s, t }' >"$tmp/path_nested_keys.json"
mkdir "$tmp/model"
printf 'mtllib ../outside.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$tmp/model/mtl_up.obj"
printf 'mtllib %s/outside.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' "$tmp" >"$tmp/model/mtl_abs.obj"
printf 'newmtl m\nKd 1 0 0\n' >"$tmp/outside.mtl"
printf 'AC3Db\nMATERIAL "m" rgb 1 1 1  amb 0 0 0  emis 0 0 0  spec 0 0 0  shi 0  trans 0\nOBJECT world\nkids 1\nOBJECT poly\nnumvert 50000000\n0 0 0\n' \
  >"$tmp/huge_numvert.acc"
printf 'AC3Db\nOBJECT world\nkids 1\nOBJECT poly\nnumvert 3\n0 0 0\n1 0 0\n0 1 0\nnumsurf 1\nSURF 0x10\nrefs 3\n0 0 0\n1 0 0\n2 0 0\nkids 0\n' \
  >"$tmp/no_material.acc"
printf 'mtllib tex_abs.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n' >"$tmp/model/tex_abs.obj"
printf 'newmtl m\nKd 1 1 1\nmap_Kd %s/outside.png\n' "$tmp" >"$tmp/model/tex_abs.mtl"
printf 'mtllib tex_up.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n' >"$tmp/model/tex_up.obj"
printf 'newmtl m\nKd 1 1 1\nmap_Kd ../outside.png\n' >"$tmp/model/tex_up.mtl"
printf 'mtllib tex_big.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n' >"$tmp/model/tex_big.obj"
printf 'newmtl m\nKd 1 1 1\nmap_Kd big.png\n' >"$tmp/model/tex_big.mtl"
printf 'not a folder\n' >"$tmp/a_file"
ln -s loop_b "$tmp/loop_a"
ln -s loop_a "$tmp/loop_b"
printf 'mtllib mtl_self.obj\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$tmp/model/mtl_self.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\np 1\n' >"$tmp/lines_only.obj"
printf '{"asset": {"version": "1.0"}, "bufferViews": {"v": {"buffer": "b", "byteLength": 36}}}' \
  >"$tmp/v1.gltf"
printf 'glTF\001\000\000\000\030\000\000\000\004\000\000\000JSON{}  ' >"$tmp/v1.glb"
awk 'BEGIN { print "v 0 0 0\nv 1 0 0\nv 0 1 0"; for (i = 0; i < 20000; i++) print "f 1 2 3" }' \
  >"$tmp/faces20k.obj"
# 200000 copies of one face (was > 50 minutes for a default walk). Only written when used.
if [[ $command == *faces200k.obj* ]]; then
  awk 'BEGIN { print "v 0 0 0\nv 1 0 0\nv 0 1 0"; for (i = 0; i < 200000; i++) print "f 1 2 3" }' \
    >"$tmp/faces200k.obj"
fi
# 80 MB of 'f 1 2 3' (10 million faces): took 42 s and 3 GB, then a bare
# std::bad_alloc. Only written when used.
if [[ $command == *faces80mb.obj* ]]; then
  { printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n'; yes 'f 1 2 3' | head -n 10000000; } >"$tmp/faces80mb.obj"
fi
# LightWave scenes naming their object by a bare name, as LWS does: one
# beside the scene, one in the folder above; a decoy of the same name in
# another folder, the working directory of the rows that use it.
mkdir -p "$tmp/model/lws" "$tmp/elsewhere"
python3 - "$tmp" <<'PYEOF' || { echo "FAIL $id: python3 is needed to write the LWO fixtures"; exit 1; }
import struct, sys
t = sys.argv[1]
def chunk(tag, data, size='>I'):
    if len(data) % 2: data += b'\0'
    return tag + struct.pack(size, len(data)) + data
def s0(s):
    b = s.encode() + b'\0'
    return b + (b'\0' if len(b) % 2 else b'')
def lwo(path):  # LWO2: one layer, a unit quad as two triangles, one surface
    pts = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)]
    body = b'LWO2' + chunk(b'TAGS', s0('Default'))
    body += chunk(b'LAYR', struct.pack('>HH3f', 0, 0, 0, 0, 0) + s0(''))
    body += chunk(b'PNTS', b''.join(struct.pack('>3f', *p) for p in pts))
    body += chunk(b'POLS', b'FACE' + struct.pack('>8H', 3, 0, 1, 2, 3, 1, 3, 2))
    body += chunk(b'PTAG', b'SURF' + struct.pack('>4H', 0, 0, 1, 0))
    body += chunk(b'SURF', s0('Default') + s0('') + chunk(b'COLR', struct.pack('>3fH', 0.8, 0.2, 0.2, 0), '>H'))
    open(path, 'wb').write(b'FORM' + struct.pack('>I', len(body)) + body)
lwo(t + '/model/lws/beside.lwo')
lwo(t + '/model/outside.lwo')
lwo(t + '/elsewhere/beside.lwo')
open(t + '/model/lws/beside.lws', 'w').write('LWSC\n5\n\nLoadObjectLayer 1 10000000 beside.lwo\n')
open(t + '/model/lws/up.lws', 'w').write('LWSC\n5\n\nLoadObjectLayer 1 10000000 ../outside.lwo\n')
PYEOF
python3 - "$tmp" <<'EOF' || { echo "FAIL $id: python3 is needed to write the hostile fixtures"; exit 1; }
import base64, json, os, socket, struct, sys, zlib
t = sys.argv[1]
def png(path, w, h, idat=None):
    def chunk(kind, data):
        return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data))
    raw = b''.join(b'\0' + bytes((x * 7 + y * 3) % 256 for x in range(w * 3)) for y in range(h)) \
        if idat is None else None
    body = zlib.compress(raw) if idat is None else idat
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0))
                           + chunk(b'IDAT', body) + chunk(b'IEND', b''))
png(t + '/a.png', 32, 32)
png(t + '/outside.png', 16, 16)
png(t + '/b.png', 32, 32)
png(t + '/tiny_a.png', 5, 5)
png(t + '/tiny_b.png', 5, 5)
# Header says 12000x12000; only the header is read before the size is refused.
png(t + '/huge.png', 12000, 12000, idat=zlib.compress(b'\0' * 1000))
# Past stb_image's own limits (2^30 bytes decoded, 2^24 a side): named as sizes too.
png(t + '/huge30k.png', 30000, 30000, idat=zlib.compress(b'\0' * 1000))
png(t + '/huge64k.png', 65536, 65536, idat=zlib.compress(b'\0' * 1000))
# 1024x1024 of zeros (4 MiB decoded): over a 3 MiB --max-memory.
png(t + '/model/big.png', 1024, 1024, idat=zlib.compress(b'\0' * (1 + 1024 * 3) * 1024))
s = socket.socket(socket.AF_UNIX)
s.bind(t + '/sock.png')
s.close()
# One triangle; buffer given by the caller.
def gltf(path, uri, offset=0):
    tri = struct.pack('<9f', 0, 0, 0, 1, 0, 0, 0, 1, 0)
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                          "min": [0, 0, 0], "max": [1, 1, 0]}],
           "bufferViews": [{"buffer": 0, "byteOffset": offset, "byteLength": 36}],
           "buffers": [{"uri": uri, "byteLength": 36}]}
    open(path, 'w').write(json.dumps(doc))
    return tri
tri = gltf(t + '/model/buf_up.gltf', '../outside.bin')
open(t + '/outside.bin', 'wb').write(tri)
gltf(t + '/model/buf_abs.gltf', t + '/outside.bin')
gltf(t + '/model/buf_fifo.gltf', 'fifo.bin')
gltf(t + '/wrap.gltf', 'data:application/octet-stream;base64,' + base64.b64encode(tri).decode(),
     offset=2**64 - 4)
os.mkfifo(t + '/model/fifo.bin')
# 100 000 levels of nesting inside an otherwise valid glTF.
n = 100000
open(t + '/nested.gltf', 'w').write('{"asset": {"version": "2.0"}, "extras": ' + '[' * n + ']' * n + '}')
# 22-byte .glb whose JSON chunk claims nearly 4 GiB.
open(t + '/huge_chunk.glb', 'wb').write(b'glTF' + struct.pack('<III', 2, 22, 0xFFFFFFF0) + b'JSON' + b'{}')
open(t + '/big_total.glb', 'wb').write(b'glTF' + struct.pack('<III', 2, 0x7FFFFFFF, 2) + b'JSON' + b'{}')
EOF
# Keyframe database surgery: hw64 (docs/keyframe-db.md) re-checksums what a
# row changed, so the damage gets past the checksums and must be caught by
# the checks behind them. Usage: python3 {tmp}/hwdb.py COMMAND DB [ARGS].
cat >"$tmp/hwdb.py" <<'EOF'
import json, struct, sys
M = (1 << 64) - 1
def hw64(b, seed=0x6877646232303236):
    h = seed
    for i in range(0, len(b), 8):
        w = int.from_bytes(b[i:i + 8].ljust(8, b'\0'), 'little')
        x = h ^ w
        h = (((x << 31) | (x >> 33)) & M) * 0x9E3779B97F4A7C15 & M
    h ^= len(b)
    h ^= h >> 30; h = h * 0xBF58476D1CE4E5B9 & M
    h ^= h >> 27; h = h * 0x94D049BB133111EB & M
    h ^= h >> 31
    return h
def load(db): return json.load(open(db + '/index.json'))
def save(db, ix):
    ix.pop('index_checksum', None)
    ix['index_checksum'] = '%016x' % hw64(json.dumps(ix, sort_keys=True, separators=(',', ':')).encode())
    open(db + '/index.json', 'w').write(json.dumps(ix, indent=1))
def reseal(path):  # payload and header checksums after an edit
    b = bytearray(open(path, 'rb').read())
    b[40:48] = struct.pack('<Q', hw64(bytes(b[64:])))
    b[48:56] = struct.pack('<Q', hw64(bytes(b[:48])))
    open(path, 'wb').write(bytes(b))
    return len(b), hw64(bytes(b[64:]))
def fix_entry(db, frame):
    ix = load(db)
    for e in ix['keyframes']:
        if e['frame'] == frame:
            b = open(db + '/' + e['file'], 'rb').read()
            e['bytes'] = len(b); e['checksum'] = '%016x' % hw64(b[64:])
    save(db, ix)
cmd, db = sys.argv[1], sys.argv[2]
ix = load(db) if cmd != "chunk-checksum" else None
if cmd == 'drop-last':        # lose an entry, keep the old index checksum
    ix['keyframes'].pop(); open(db + '/index.json', 'w').write(json.dumps(ix, indent=1))
elif cmd == 'drop-last-reseal':
    ix['keyframes'].pop(); save(db, ix)
elif cmd == 'frame':          # set entry 0's frame number
    ix['keyframes'][0]['frame'] = int(sys.argv[3]); save(db, ix)
elif cmd == 'no-checksum':
    ix.pop('index_checksum'); open(db + '/index.json', 'w').write(json.dumps(ix, indent=1))
elif cmd == 'extra':          # another walk's keyframe listed under a new frame
    e = dict(ix['keyframes'][0]); e['frame'] = int(sys.argv[3]); ix['keyframes'].append(e); save(db, ix)
elif cmd == 'fix':            # after a keyframe file was replaced
    fix_entry(db, int(sys.argv[3]))
elif cmd == 'nan-quad':       # first quad's first world corner x := NaN, file re-sealed
    e = ix['keyframes'][0]; path = db + '/' + e['file']
    b = bytearray(open(path, 'rb').read())
    w, h = struct.unpack('<ii', b[20:28])
    at = 64 + 132 + 16 + w * h * 17 + 56 + 16
    b[at:at + 8] = struct.pack('<d', float('nan'))
    open(path, 'wb').write(bytes(b)); reseal(path); fix_entry(db, e['frame'])
elif cmd == 'chunk-checksum':  # a chunk result's checksum made non-hex
    import glob
    f = sorted(glob.glob(db + '/.chunks/*.json'))
    f = [x for x in f if 'plan' not in x][0]
    r = json.load(open(f)); r['entries'][0]['checksum'] = 'zz' * 8; json.dump(r, open(f, 'w'))
EOF

case $setup in
  -) ;;
  tmpfs:*) mkdir "$out" && mount -t tmpfs -o "size=${setup#tmpfs:}" hwcat "$out" ||
    { echo "FAIL $id: cannot mount a ${setup#tmpfs:} tmpfs at $out"; exit 1; } ;;
  tmpfs-ro) mkdir "$out" && mount -t tmpfs -o ro,size=64k hwcat "$out" ||
    { echo "FAIL $id: cannot mount a read-only tmpfs at $out"; exit 1; } ;;
  foreign) mkdir "$out" && echo data >"$out/thesis.tmp-999999" && echo notes >"$out/notes.txt" ;;
  pre:*)
    pre=${setup#pre:}
    pre=${pre//\{hw\}/$hw}
    pre=${pre//\{tmp\}/$tmp}
    pre=${pre//\{out\}/$out}
    (cd "$tmp" && env -u HW_GL_FAIL timeout -k 10 "$timeout_s" bash -c "$pre") \
      >"$tmp/pre.log" 2>&1 </dev/null ||
      { echo "FAIL $id: setup failed: $pre"; sed 's/^/  /' "$tmp/pre.log" | tail -5; exit 1; } ;;
  *) echo "FAIL $id: unknown setup '$setup'"; exit 1 ;;
esac

# What {out} holds: every entry's path, kind, size and content hash.
snapshot() {
  [ -e "$out" ] || { echo absent; return; }
  (cd "$out" && find . -printf '%p %y %s\n' | sort && find . -type f -print0 | sort -z |
    xargs -0r sha1sum)
}
before=$(snapshot)

# ------------------------------------------------------------------- run ----
command=${command//\{hw\}/$hw}
command=${command//\{tmp\}/$tmp}
command=${command//\{out\}/$out}
command=${command//\{src\}/$src}
regex=${regex//\{out\}/$out}
regex=${regex//\{tmp\}/$tmp}
# Runs from the fixture dir with stdin closed; HW_GL_FAIL is cleared so only
# the rows that set it see a failing context. The scene cache and DISPLAY are
# left as they are unless a row overrides them with env.
(cd "$tmp" && exec env -u HW_GL_FAIL timeout -k 10 "$timeout_s" bash -c "$command") \
  >"$tmp/stdout" 2>"$tmp/stderr" </dev/null
code=$?

ok=1
problem() { echo "FAIL $id: $*"; ok=0; }
if [ $code -eq 124 ] || [ $code -eq 137 ]; then
  problem "no answer within ${timeout_s} s (a hang)"
elif [ $code -ge 128 ]; then
  problem "crashed: exit $code (signal $((code - 128)))"
elif [ $code -eq 0 ]; then
  problem "exit 0: the bad input was accepted"
elif ! [[ $code =~ ^($want_exit)$ ]]; then
  problem "exit $code, expected $want_exit"
fi
if ! grep -qiE -- "$regex" "$tmp/stderr"; then
  problem "stderr does not match /$regex/"
fi
leftover=
case $clean in
  empty) [ -e "$out" ] && leftover=$(cd "$out" && find . -mindepth 1 | sort) ;;
  no-partial) [ -e "$out" ] && leftover=$(cd "$out" && find . \( -name '*.tmp-*' -o \
    -name report.json -o -name render.json \) | sort) ;;
  untouched) [ "$(snapshot)" = "$before" ] ||
    leftover="changed: $(diff <(echo "$before") <(snapshot) | grep '^[<>]' | head -5)" ;;
  *) problem "unknown clean policy '$clean'" ;;
esac
[ -n "$leftover" ] && problem "left in the output dir ($clean): $(echo $leftover)"

if [ $ok -eq 0 ]; then
  echo "  row: $description"
  echo "  command: $command"
  echo "  exit: $code"
  echo "  stderr:"; head -c 2000 "$tmp/stderr" | sed 's/^/    /'
  exit 1
fi
echo "ok $id: exit $code, $(grep -m1 -iE -- "$regex" "$tmp/stderr" | head -c 300)"
