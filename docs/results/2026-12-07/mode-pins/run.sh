#!/bin/bash
# --mode auto's choices measured and pinned: each scene's walk (512², the
# defaults) three times with a fresh pin folder: run 1 chooses from its own
# costs and pins them, run 2 replays the pin (as a second run of the same
# command does), run 3 chooses again with --auto-pin off. Run 1 against run 3
# is how far two measured runs agree; run 1 against run 2, two runs as a user
# gets them.
# Usage: run.sh BIN OUT
# Then: /usr/bin/python3 summarise.py OUT   (writes results.csv, results.json, agreement.png here)
set -euo pipefail
bin=$1; out=$2
mkdir -p "$out"
export HYBRIDWALK_PINS="$out/pins"
rm -rf "$HYBRIDWALK_PINS"
scenes=(indoor indoor:1M q3:oa_dm5 q3:ps37ctf morse:tum_kitchen/tum_kitchen outdoor torcs:forza)
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../../../.." && pwd)
for sc in "${scenes[@]}"; do
  extra=()
  case $sc in
    q3:oa_dm5) extra=(--path "$repo/paths/oa_dm5.json") ;;
    q3:ps37ctf) extra=(--path "$repo/paths/ps37ctf.json") ;;
    torcs:forza) extra=(--path "$repo/paths/forza.json") ;;
  esac
  for run in 1 2 3; do
    pin=()
    [ "$run" = 3 ] && pin=(--auto-pin off)
    name=$(echo "$sc" | tr ':/' '__')-$run
    echo "$name" >&2
    "$bin" walk --scene "$sc" "${extra[@]}" "${pin[@]}" --out "$out/$name" --quiet >/dev/null
  done
done
