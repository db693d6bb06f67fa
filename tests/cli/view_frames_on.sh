#!/usr/bin/env bash
# view --frames-on gpu|cpu|auto with OpenGL's warper: frames kept on the GPU
# and frames read back and composed on the CPU give the same window, pixel for
# pixel (screenshots compared with cmp after decoding); a bad value is a usage
# error (exit 2) naming the choices. Runs under Xvfb (scripts/test.sh runs
# CTest in xvfb-run).
# Usage: view_frames_on.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
cd "$tmp"
run() {  # $1 = --frames-on value, $2 = screenshot
  LP_NUM_THREADS=2 "$hw" view --scene indoor:20k --play --exit-after 12 --width 256 --height 192 \
    --warper gl --mode hybrid --no-hud --frames-on "$1" --screenshot "$2" > "$2.log" 2>&1
}
check "frames on the GPU: runs" run gpu gpu.png
check "frames on the CPU: runs" run cpu cpu.png
check "auto: runs" run auto auto.png
# The same pixels (PNG files may differ only in encoding; compare the RGB).
same_pixels() {
  python3 - "$1" "$2" <<'PY'
import sys, zlib, struct
def pixels(path):
    data = open(path, 'rb').read()
    idat = b''
    pos = 8
    while pos < len(data):
        n, kind = struct.unpack('>I4s', data[pos:pos + 8])
        if kind == b'IDAT': idat += data[pos + 8:pos + 8 + n]
        if kind == b'IHDR': w, h = struct.unpack('>II', data[pos + 8:pos + 16])
        pos += 12 + n
    return w, h, zlib.decompress(idat)
a, b = pixels(sys.argv[1]), pixels(sys.argv[2])
sys.exit(0 if a == b and len(a[2]) > 1000 else 1)
PY
}
check "gpu and cpu: the same pixels" same_pixels gpu.png cpu.png
check "auto: the same pixels" same_pixels auto.png cpu.png
# Not a blank window: the decoded (filtered) rows hold many distinct byte triples.
check "not blank" python3 -c "
import zlib, struct
d = open('gpu.png', 'rb').read()
pos, idat = 8, b''
while pos < len(d):
    n, kind = struct.unpack('>I4s', d[pos:pos + 8])
    if kind == b'IDAT': idat += d[pos + 8:pos + 8 + n]
    pos += 12 + n
raw = zlib.decompress(idat)
assert len({raw[i:i + 3] for i in range(0, len(raw) - 3, 3)}) > 500"
"$hw" view --scene indoor:20k --frames-on disk > bad.log 2>&1
code=$?
check "bad value: exit 2" [ "$code" -eq 2 ]
check "bad value: names the choices" grep -q "disk not in {auto,gpu,cpu}" bad.log
finish
