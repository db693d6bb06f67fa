# References an OBJ makes (docs/bad-input.md, "Scene files"): a missing
# mtllib is warned about exactly once and the model still renders (exit 0);
# the same model with its .mtl present loads without the warning.
# Args: HYBRIDWALK SOURCE_DIR.
src=$(realpath "$2")
. "$src/tests/cli/lib.bash"
hw=$(realpath "$hw")
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}
cd "$tmp"
mkdir m
printf 'mtllib gone.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >m/model.obj
"$hw" render --scene m/model.obj --frames 1 --width 32 --height 32 --out o1 >/dev/null 2>o1.err
check missing-mtllib-exit-0 [ $? -eq 0 ]
check missing-mtllib-warned-once [ "$(grep -c "model.obj: mtllib 'gone.mtl' not found" o1.err)" -eq 1 ]
check missing-mtllib-rendered [ -f o1/render.json ]
printf 'newmtl red\nKd 1 0 0\n' >m/gone.mtl
"$hw" render --scene m/model.obj --frames 1 --width 32 --height 32 --out o2 >/dev/null 2>o2.err
check present-mtllib-exit-0 [ $? -eq 0 ]
check present-mtllib-no-warning [ "$(grep -c "mtllib" o2.err)" -eq 0 ]
finish
