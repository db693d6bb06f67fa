#!/usr/bin/env bash
# Every compose mode × fallback × scene of this study for the LOD settings in
# $HW_LODS (paper, rl; default paper), one walk each, sequentially. Usage:
#   [HW_LODS="paper rl"] run.sh HYBRIDWALK OUTROOT
set -u
hw=${1:?hybridwalk binary}
root=${2:?output root}
src=$(cd "$(dirname "$0")/../../../.." && pwd)
export LP_NUM_THREADS=2
declare -A scene=( [oa_dm5]="--scene q3:oa_dm5 --path $src/paths/oa_dm5.json"
                   [forza]="--scene torcs:forza --path $src/paths/forza.json"
                   [indoor]="--scene indoor"
                   [sharp_turn]="--scene indoor --path $src/paths/indoor_sharp_turn.json" )
declare -A lod=( [paper]="" [rl]="--planarity region-local --merge-strips --tau-px 0.125" )
for l in ${HW_LODS:-paper}; do
  for s in indoor sharp_turn oa_dm5 forza; do
    for c in overlay depth-merge blend; do
      for f in copy reproject; do
        out="$root/$s/$l/$c-$f"
        [ -s "$out/report.json" ] && continue
        mkdir -p "$root/$s/$l"
        echo "== $s $l $c $f $(date +%T)"
        $hw walk ${scene[$s]} ${lod[$l]} --compose $c --fallback $f --strips 4 --quiet \
          --out "$out" > "$out.log" 2>&1 || { mkdir -p "$out"; echo "FAILED $s $l $c $f"; tail -3 "$out.log"; }
      done
    done
  done
done
