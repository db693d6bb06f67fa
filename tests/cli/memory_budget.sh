# The whole-run memory budget (docs/bad-input.md, --max-memory), under
# ulimit -v 4000000 (3.8 GiB of address space; default budget 40 % of it):
#  - an OBJ naming six RLE TGAs of 16384x16384 (1 GiB decoded each, 8 MiB on
#    disk), --max-texture-size 16384 so each passes the per-texture cap: one
#    line naming the second texture, the total and the budget; exit 1;
#  - an 80 MB OBJ of 10 M faces "f 1 2 3" (Assimp would need ~6 GB): refused
#    from its counted faces before Assimp reads it, naming the file;
#  - --max-memory refuses a bare number and accepts a unit; a small budget
#    refuses a model that loads under the default;
#  - no output folder is left behind by a refused load.
# Args: HYBRIDWALK SOURCE_DIR.
src=$(realpath "$2")
. "$src/tests/cli/lib.bash"
hw=$(realpath "$hw")
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}
cd "$tmp"

python3 - <<'PY'
import struct, os
def tga(path, side, rgb):  # run-length encoded: 128 pixels of one colour per packet
    hdr = struct.pack('<BBBHHBHHHHBB', 0, 0, 10, 0, 0, 0, 0, 0, side, side, 24, 0x20)
    open(path, 'wb').write(hdr + (bytes([0x80 | 127]) + bytes(rgb)) * (side * side // 128))
os.makedirs('tex')
mtl, obj = [], ['mtllib big.mtl', 'v 0 0 0', 'v 1 0 0', 'v 1 1 0', 'v 0 1 0',
                'vt 0 0', 'vt 1 0', 'vt 1 1', 'vt 0 1']
for i in range(6):
    tga('tex/t%d.tga' % i, 16384, (40 * i, 100, 200))
    mtl += ['newmtl m%d' % i, 'Kd 1 1 1', 'map_Kd t%d.tga' % i]
    obj += ['usemtl m%d' % i, 'f 1/1 2/2 3/3 4/4']
open('tex/big.mtl', 'w').write('\n'.join(mtl) + '\n')
open('tex/big.obj', 'w').write('\n'.join(obj) + '\n')
with open('faces.obj', 'w') as f:
    f.write('v 0 0 0\nv 1 0 0\nv 0 1 0\n')
    f.write('f 1 2 3\n' * 10000000)
with open('small.obj', 'w') as f:
    f.write('v 0 0 0\nv 1 0 0\nv 0 1 0\n')
    f.write('f 1 2 3\n' * 3000)
PY

limited() { (ulimit -v 4000000; "$hw" "$@"); }
render=(render --frames 1 --width 32 --height 32)

limited "${render[@]}" --scene tex/big.obj --max-texture-size 16384 --out o1 >o1.out 2>o1.err
check textures-exit-1 [ $? -eq 1 ]
check textures-one-line [ "$(grep -c . o1.err)" -le 2 ]
check textures-message grep -qE \
  "t[1-5]\.tga: texture 16384x16384 decoded \(1\.0 GiB; 2\.0 GiB with what the run holds already\), over the 1\.[0-9] GiB memory budget; --max-memory" o1.err
check textures-no-output [ ! -e o1 ]

limited "${render[@]}" --scene faces.obj --out o2 >o2.out 2>o2.err
check faces-exit-1 [ $? -eq 1 ]
check faces-message grep -qE \
  "faces\.obj: importing 10000000 faces \(30000000 vertex references\) needs about \([0-9.]+ GiB\), over the 1\.[0-9] GiB memory budget" o2.err
check faces-no-output [ ! -e o2 ]

"$hw" "${render[@]}" --scene small.obj --max-memory 4 --out o3 >/dev/null 2>o3.err
check bare-number-exit-2 [ $? -eq 2 ]
check bare-number-message grep -q "expected a size with a unit, e.g. 4G" o3.err
"$hw" "${render[@]}" --scene small.obj --max-memory 1M --out o4 >/dev/null 2>o4.err
check small-budget-refused [ $? -eq 1 ]
check small-budget-message grep -qE "small\.obj: importing 3000 faces .* over the 1\.0 MiB memory budget" o4.err
"$hw" "${render[@]}" --scene small.obj --max-memory 64M --out o5 >/dev/null 2>o5.err
check budget-with-unit-loads [ $? -eq 0 ]
finish
