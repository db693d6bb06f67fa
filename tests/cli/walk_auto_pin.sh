#!/usr/bin/env bash
# walk --auto-pin: the first auto walk pins its choices in $HYBRIDWALK_PINS,
# the second replays them (same modes frame by frame) and says so on stdout;
# --auto-pin off neither reads nor writes; a folder that cannot be made
# leaves the walk as it is (exit 0) and the report says why.
# Usage: walk_auto_pin.sh HYBRIDWALK SOURCE_DIR
source "$(dirname "$0")/lib.bash"
export HYBRIDWALK_PINS="$tmp/pins"
walk() {  # NAME [OPTIONS...]
  local name=$1; shift
  "$hw" walk --scene indoor:20k --frames 23 --strips 0 --no-reference "$@" \
    --out "$tmp/$name" --quiet >"$tmp/$name.stdout" 2>"$tmp/$name.stderr"
  local rc=$?
  check "$name walk exits 0 ($(tail -2 "$tmp/$name.stderr"))" test $rc -eq 0
}
summary() {  # NAME KEY -> summary.auto_pin.KEY
  python3 -c "import json,sys; print(json.load(open('$tmp/$1/report.json'))['summary']['auto_pin']['$2'])"
}
modes() {
  python3 -c "import json; print(''.join(f['mode'][0] for f in json.load(open('$tmp/$1/report.json'))['frames']))"
}
walk first
check "first run measured" test "$(summary first state)" = measured
check "one pin written in \$HYBRIDWALK_PINS" test "$(ls "$tmp/pins" | wc -l)" -eq 1
pin=$(ls "$tmp"/pins/walk-*.json)
check "the pin holds 23 modes" python3 -c "
import json,sys; p=json.load(open('$pin')); sys.exit(0 if p['frames'] == 23 and len(p['modes']) == 23 else 1)"
check "stdout names the pin" grep -q "pinned to $pin" "$tmp/first.stdout"

walk second
check "second run replayed" test "$(summary second state)" = replayed
check "same modes frame by frame" test "$(modes first)" = "$(modes second)"
check "stdout says the choices were replayed" grep -q "chosen as a measured run of this walk pinned them" "$tmp/second.stdout"

# With the frames saved (an output option: the same pin) and keyframes built
# in the frame: the replay's frames are the measured run's, byte for byte.
walk saved1 --save-frames --sync-keyframes
walk saved2 --save-frames --sync-keyframes
check "saved walk replayed" test "$(summary saved2 state)" = replayed
same=1
for f in "$tmp"/saved1/frames/*.png; do
  cmp -s "$f" "$tmp/saved2/frames/$(basename "$f")" || { echo "  differs: $(basename "$f")"; same=0; }
done
check "replayed frames identical to the measured run's" test $same -eq 1

walk other --tau-px 0.25
check "another option: measured, another pin" test "$(ls "$tmp/pins" | wc -l)" -eq 3

rm -rf "$tmp/pins"
walk off --auto-pin off
check "--auto-pin off: state off" test "$(summary off state)" = off
check "--auto-pin off writes nothing" test ! -e "$tmp/pins"

: >"$tmp/not-a-folder"
HYBRIDWALK_PINS="$tmp/not-a-folder/pins" walk unwritable
check "an unusable pin folder: measured, not pinned" test "$(summary unwritable state)" = "measured, not pinned"
check "and the report says why" python3 -c "
import json,sys; n=json.load(open('$tmp/unwritable/report.json'))['summary']['auto_pin']['note']; print(n); sys.exit(0 if n and 'not-a-folder' in n else 1)"
finish
