# Keyframe database and chunked runs (docs/slurm.md, docs/keyframe-db.md):
#  - bake + walk --keyframes gives bit-identical frames; a corrupted or
#    truncated keyframe file is named by its checksum/size error;
#  - --workers 2 gives the in-process outputs (bake: identical files; sweep:
#    identical except timings and machine info);
#  - on a one-node Slurm cluster (scripts/slurm-cluster.sh, started here and
#    stopped on exit): --slurm bake and sweep equal the local outputs; a task
#    made to fail (HW_FAIL_CHUNK) is reported by array index and --resume
#    completes the run; SIGINT during the wait cancels the job.
# Needs Slurm + munge (scripts/setup.sh --test). Args: HYBRIDWALK SOURCE_DIR.
src=$(realpath "$2")
. "$src/tests/cli/lib.bash"
hw=$(realpath "$hw")
export LP_NUM_THREADS=${LP_NUM_THREADS:-2}
cd "$tmp"
chmod 0711 "$tmp"  # munge's socket lives below; its folders must be traversable
cluster=$tmp/slurm
export HW_SLURM_PORT=$((20000 + $$ % 20000 * 2))
trap '"$src/scripts/slurm-cluster.sh" stop "$cluster" >/dev/null 2>&1; rm -rf "$tmp"' EXIT

cat > path.json <<'EOF'
{"width": 128, "height": 128, "fov_y_deg": 60, "near": 0.05, "far": 100, "up": [0, 1, 0],
 "keys": [{"eye": [0, 1.6, 4], "look_at": [0, 1.4, 0]}, {"eye": [1, 1.6, 1], "look_at": [0, 1.4, -3]}],
 "frames": 13, "keyframe_every": 4}
EOF
common=(--scene indoor --path path.json --quiet)
sweepArgs=(sweep "${common[@]}" --tau 2^8,2^12 --no-variants --cells-per-task 2)  # 7 cells, 4 chunks

# same_sweep A B: equal except timing fields (*_ms, machine) and pareto.png,
# whose x axis is a time.
same_sweep() {
  python3 - "$1" "$2" <<'PY' || return 1
import csv, json, sys
a, b = sys.argv[1], sys.argv[2]
TIMING = {"lod_build_ms", "in_between_ms", "reference_ms", "machine"}
def strip(x):
    if isinstance(x, dict): return {k: strip(v) for k, v in x.items() if k not in TIMING}
    if isinstance(x, list): return [strip(v) for v in x]
    return x
ja, jb = (strip(json.load(open(d + "/sweep.json"))) for d in (a, b))
if ja != jb or len(ja["rows"]) < 6:
    print("sweep.json differs beyond timings (or too few rows):", a, b); sys.exit(1)
def table(d):
    return [{k: v for k, v in r.items() if "_ms" not in k} for r in csv.DictReader(open(d + "/sweep.csv"))]
if table(a) != table(b):
    print("sweep.csv differs beyond its timing columns:", a, b); sys.exit(1)
PY
  local f
  for f in quads_vs_tau.png psnr_vs_tau.png $(cd "$1" && ls overlays/*.png); do
    cmp -s "$1/$f" "$2/$f" || { echo "$f differs: $1 $2"; return 1; }
  done
  [ -s "$2/index.html" ] && [ -s "$2/pareto.png" ] && [ ! -e "$2/.chunks" ]
}
same_db() { diff -r -x .hybridwalk-owner.json "$1" "$2" >/dev/null && [ ! -e "$2/.chunks" ] && [ -s "$2/index.json" ]; }

# ---- local: database and workers -------------------------------------------
check bake "$hw" bake "${common[@]}" --out db
check bake-has-4-keyframes test "$(ls db/*.hwkf | wc -l)" -eq 4
check walk-live "$hw" walk --mode hybrid "${common[@]}" --out live --save-frames --strips 0
check walk-db "$hw" walk --mode hybrid "${common[@]}" --out fromdb --save-frames --strips 0 --keyframes db
same_frames() {
  local n=0 f
  for f in live/frames/*.png; do cmp -s "$f" "fromdb/frames/${f##*/}" || return 1; n=$((n + 1)); done
  [ "$n" -eq 13 ]
}
check walk-db-bit-identical-frames same_frames

cp -r db flipped
python3 -c "
f = open('flipped/kf_000004.hwkf', 'r+b'); f.seek(3000); b = f.read(1); f.seek(3000); f.write(bytes([b[0] ^ 1]))"
"$hw" walk --mode hybrid "${common[@]}" --out bad --keyframes flipped 2>err.txt
check flipped-byte-fails test $? -eq 1
check flipped-byte-named grep -q 'flipped/kf_000004.hwkf: checksum mismatch' err.txt
cp -r db cut
truncate -s 5000 cut/kf_000008.hwkf
"$hw" walk --mode hybrid "${common[@]}" --out bad --keyframes cut 2>err.txt
check truncated-fails test $? -eq 1
check truncated-named grep -q 'cut/kf_000008.hwkf: truncated' err.txt
"$hw" walk --mode hybrid "${common[@]}" --out bad --keyframes db --tau 4096 2>err.txt
check other-options-refused grep -q 'mesh.tau 2048.0, this run has 4096.0' err.txt

check bake-workers "$hw" bake "${common[@]}" --out dbw --workers 2 --keyframes-per-task 1
check bake-workers-identical same_db db dbw
check sweep-local "$hw" "${sweepArgs[@]}" --out s-local
check sweep-workers "$hw" "${sweepArgs[@]}" --out s-workers --workers 2
check sweep-workers-equal same_sweep s-local s-workers
HW_FAIL_CHUNK=3 "$hw" "${sweepArgs[@]}" --out s-wfail --workers 2 2>err.txt
check workers-failed-by-index grep -q 'worker chunks failed (indices 3)' err.txt
check workers-resume "$hw" "${sweepArgs[@]}" --out s-wfail --workers 2 --resume
check workers-resume-equal same_sweep s-local s-wfail

# ---- one-node Slurm cluster -------------------------------------------------
if ! "$src/scripts/slurm-cluster.sh" start "$cluster"; then
  echo "FAIL cluster-start (is Slurm installed? scripts/setup.sh --test)"
  failures=$((failures + 1))
  finish
  exit
fi
eval "$("$src/scripts/slurm-cluster.sh" env "$cluster")"
slurm=(--slurm --slurm-poll 0.5 --slurm-time 10 --sbatch-arg=--job-name=hw-ci)

check bake-slurm "$hw" bake "${common[@]}" --out dbs --keyframes-per-task 2 "${slurm[@]}"
check bake-slurm-identical same_db db dbs
check sweep-slurm "$hw" "${sweepArgs[@]}" --out s-slurm "${slurm[@]}"
check sweep-slurm-equal same_sweep s-local s-slurm

# A failing task: reported by array index, then --resume runs only it.
HW_FAIL_CHUNK=2 "$hw" "${sweepArgs[@]}" --out s-fail "${slurm[@]}" 2>err.txt
check failed-task-exit test $? -eq 1
check failed-task-by-index grep -q 'array indices 2)' err.txt
check failed-task-state grep -q 'array index 2: FAILED, exit code 1:0' err.txt
check failed-task-no-output test ! -e s-fail/sweep.json
check resume "$hw" "${sweepArgs[@]}" --out s-fail "${slurm[@]}" --resume
check resume-equal same_sweep s-local s-fail
HW_FAIL_CHUNK=0,1 "$hw" bake "${common[@]}" --out db-fail --keyframes-per-task 1 "${slurm[@]}" 2>err.txt
check bake-failed-by-index grep -q 'array indices 0,1)' err.txt
check bake-failed-no-index test ! -e db-fail/index.json
check bake-resume "$hw" bake "${common[@]}" --out db-fail --keyframes-per-task 1 "${slurm[@]}" --resume
check bake-resume-identical same_db db db-fail
"$hw" "${sweepArgs[@]}" --out s-fail "${slurm[@]}" --resume 2>err.txt
check resume-after-success-refused grep -q 'no interrupted sweep run' err.txt
HW_FAIL_CHUNK=0 "$hw" "${sweepArgs[@]}" --out s-fail2 "${slurm[@]}" 2>/dev/null
"$hw" "${sweepArgs[@]}" --five-point-only --out s-fail2 "${slurm[@]}" --resume 2>err.txt
check resume-other-command-refused grep -q 'made by a different command' err.txt

# SIGINT while waiting: the job is cancelled (scancel) and the queue empties.
"$hw" "${sweepArgs[@]}" --out s-int "${slurm[@]}" --sbatch-arg=--begin=now+60 2>err.txt &
pid=$!
for _ in $(seq 50); do [ -s s-int/.chunks/job-id ] && break; sleep 0.2; done
sleep 1
kill -INT "$pid"
wait "$pid"
check sigint-exit test $? -eq 1
check sigint-cancelled grep -q 'cancelled Slurm job' err.txt || cat err.txt
queue_empty() { for _ in $(seq 50); do [ -z "$(squeue -h -o %i)" ] && return 0; sleep 0.2; done; return 1; }
check sigint-queue-empty queue_empty

finish
