# Output folders (docs/output-folders.md) and bake --resume (docs/keyframe-db.md):
#  - two walks with --save-frames into one folder at once: the second fails at
#    once ("in use by PID"), the first completes, frames/ holds only its frames;
#  - bake --resume on a finished database: exit 0, "complete", the folder
#    byte-identical (marker included);
#  - a bake killed (SIGKILL) at several points, then resumed (or, when it died
#    before its plan existed, rerun): the database equals an uninterrupted one;
#    a bake whose chunk fails, then --resume: the same;
#  - a walk's temporaries left by a SIGKILL are removed by the next run, a
#    user's look-alike file is not (--force into a foreign folder).
# Args: HYBRIDWALK SOURCE_DIR.
src=$(realpath "$2")
. "$src/tests/cli/lib.bash"
hw=$(realpath "$hw")
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}
cd "$tmp"

cat > path.json <<'EOF'
{"width": 96, "height": 96, "fov_y_deg": 60, "near": 0.05, "far": 100, "up": [0, 1, 0],
 "keys": [{"eye": [0, 1.6, 4], "look_at": [0, 1.4, 0]}, {"eye": [1, 1.6, 1], "look_at": [0, 1.4, -3]}],
 "frames": 25, "keyframe_every": 2}
EOF
bake=(bake --scene indoor:20k --path path.json --quiet --workers 2 --keyframes-per-task 2)

# The database files (not the marker, not the chunk work folder).
same_db() { diff -r -x .hybridwalk-owner.json -x .chunks "$1" "$2"; }

# --- one writer at a time ---
"$hw" walk --scene indoor:20k --path path.json --save-frames --strips 0 --quiet --out w \
  >/dev/null 2>w1.err &
first=$!
for _ in $(seq 100); do [ -s w/.hybridwalk-owner.json ] && break; sleep 0.05; done
"$hw" walk --scene indoor:20k --path path.json --frames 5 --width 64 --height 64 --save-frames \
  --quiet --out w >/dev/null 2>w2.err
second=$?
wait $first
check first-completes [ $? -eq 0 ]
check second-refused [ $second -eq 1 ]
check second-says-in-use grep -qE "w is in use by PID $first \(walk, started [0-9T:-]+Z\)" w2.err
check frames-of-one-run [ "$(ls w/frames | wc -l)" -eq 25 ]
check frames-one-size python3 -c "
import struct, glob, sys
sizes = {struct.unpack('>II', open(f, 'rb').read()[16:24]) for f in glob.glob('w/frames/*.png')}
sys.exit(0 if sizes == {(96, 96)} else 1)"

# --- bake --resume on a finished database ---
"$hw" "${bake[@]}" --out ref >/dev/null 2>&1
check ref-baked [ -f ref/index.json ]
cp -a ref ref.copy
"$hw" "${bake[@]}" --out ref --resume >resume.out 2>resume.err
check finished-resume-exit-0 [ $? -eq 0 ]
check finished-resume-says-complete grep -q "ref is complete" resume.out
check finished-resume-byte-identical diff -r ref ref.copy

# --- killed at several points, then resumed ---
for delay in 0.2 0.6 1.0 1.5; do
  rm -rf k
  "$hw" "${bake[@]}" --out k >/dev/null 2>&1 &
  pid=$!
  sleep $delay
  kill -KILL $pid 2>/dev/null
  wait $pid 2>/dev/null
  sleep 0.3  # workers get SIGTERM from the kernel when their parent dies
  if [ -f k/.chunks/plan.json ]; then
    "$hw" "${bake[@]}" --out k --resume >/dev/null 2>"k-$delay.err"
  elif [ -f k/index.json ]; then  # finished before the kill
    "$hw" "${bake[@]}" --out k --resume >/dev/null 2>"k-$delay.err"
  else  # killed before its plan: nothing to resume, says so, then a fresh run
    "$hw" "${bake[@]}" --out k --resume >/dev/null 2>"k-$delay.err"
    check "killed-$delay-nothing-to-resume" grep -q "there is no interrupted bake" "k-$delay.err"
    "$hw" "${bake[@]}" --out k >/dev/null 2>>"k-$delay.err"
  fi
  check "killed-$delay-resumed" [ $? -eq 0 ]
  check "killed-$delay-equals-uninterrupted" same_db ref k
done

# --- a chunk fails, then --resume ---
HW_FAIL_CHUNK=1 "$hw" "${bake[@]}" --out f >/dev/null 2>f.err
check failed-chunk-exit-1 [ $? -eq 1 ]
check failed-chunk-no-index [ ! -e f/index.json ]
"$hw" "${bake[@]}" --out f --resume >/dev/null 2>f2.err
check failed-chunk-resumed [ $? -eq 0 ]
check failed-chunk-equals-uninterrupted same_db ref f

# --- a killed run's temporaries go, a user's look-alike stays ---
mkdir t
echo data >t/thesis.tmp-999999
"$hw" walk --scene indoor:20k --path path.json --frames 3 --strips 0 --quiet --out t \
  >/dev/null 2>t1.err
check foreign-refused [ $? -eq 1 ]
"$hw" walk --scene indoor:20k --path path.json --frames 3 --strips 0 --quiet --out t --force \
  >/dev/null 2>t2.err
check forced-walk [ $? -eq 0 ]
killed=$(python3 -c "import json; print(json.load(open('t/.hybridwalk-owner.json'))['pid'])")
# What a SIGKILLed run with that PID would have left:
python3 - <<'EOF'
import json
m = json.load(open('t/.hybridwalk-owner.json')); m['pid'] = 999998
json.dump(m, open('t/.hybridwalk-owner.json', 'w'))
EOF
echo x >t/report.json.tmp-999998
"$hw" walk --scene indoor:20k --path path.json --frames 3 --strips 0 --quiet --out t \
  >/dev/null 2>t3.err
check rerun [ $? -eq 0 ]
check killed-temporary-removed [ ! -e t/report.json.tmp-999998 ]
check removal-noted grep -q "removed t/report.json.tmp-999998" t3.err
check look-alike-kept [ -f t/thesis.tmp-999999 ]
check marker-names-last-run python3 -c "
import json, sys; sys.exit(json.load(open('t/.hybridwalk-owner.json'))['pid'] in (999998, $killed))"
finish
