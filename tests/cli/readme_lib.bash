# Shared by readme_tasks.sh and readme_tasks_maps.sh (sourced after lib.bash,
# not a test itself): the README's task commands, run as a new user would,
# from the root of a fresh clone, each ```sh block in a clone of its own (a
# block is what a user copies at once: no task leans on another's output).
#   readme_commands SRC    every command of the README's ```sh blocks, one a
#                          line as "BLOCK<tab>COMMAND", comments cut (the two
#                          tests split them: the ones that need downloaded
#                          scenes, and the rest)
#   readme_maps_re         what marks a command as needing downloaded scenes
#   readme_clone SRC       a fresh clone of SRC in $clone ($tmp/clone.N; the
#                          working tree's README.md, .gitignore and paths/
#                          copied over it, so that what is tested is what is
#                          being edited), and `hybridwalk` on PATH
#   readme_run CMD         run CMD in $clone; exit 0, no "nan"; a walk prints
#                          its summary line first and writes index.html; a
#                          sweep names its pipeline. Output in $last_out.
#   readme_left_clean      nothing left in $clone outside out/ (untracked or
#                          ignored), and out/ ignored
#   readme_file PATH       PATH in whichever clone has it
readme_maps_re=$'q3:|torcs:|\thybridwalk scenes '

readme_commands() {
  awk '/^```sh/{on=1; n++; next} /^```/{on=0} on {print n "\t" $0}' "$1/README.md" |
    sed 's/[[:space:]]*#.*$//' | grep -E $'^[0-9]+\t(hybridwalk|python3|mkdir|xvfb-run)'
}

readme_clones=0
readme_clone() {
  local src=$1
  readme_clones=$((readme_clones + 1))
  clone=$tmp/clone.$readme_clones
  mkdir -p "$tmp/bin"
  ln -sf "$(readlink -f "$hw")" "$tmp/bin/hybridwalk"
  export PATH="$tmp/bin:$PATH"
  git clone -q "$src" "$clone" 2>"$tmp/clone.err"
  check "a fresh clone of $src (a git checkout is needed: $(tail -1 "$tmp/clone.err"))" \
    test -f "$clone/README.md"
  cp "$src/README.md" "$src/.gitignore" "$clone/"
  cp "$src"/paths/*.json "$clone/paths/"
}

# readme_each SRC FILE FUNCTION: for each block of FILE (readme_commands'
# lines), a fresh clone, FUNCTION CMD for each of its commands, and the
# clone checked clean afterwards.
readme_each() {
  local src=$1 file=$2 fn=$3 block cmd last=
  while IFS=$'\t' read -r block cmd; do
    if [ "$block" != "$last" ]; then
      [ -n "$last" ] && readme_left_clean
      readme_clone "$src"
      echo "README block $block: $clone"
      last=$block
    fi
    "$fn" "$cmd"
  done <"$file"
  [ -n "$last" ] && readme_left_clean
}

readme_n=0
readme_run() {
  local cmd=$1 out rc
  readme_n=$((readme_n + 1))
  last_out=$tmp/out$readme_n
  (cd "$clone" && bash -c "$cmd") </dev/null >"$last_out" 2>"$tmp/err$readme_n"
  rc=$?
  check "exits 0: $cmd ($(tail -1 "$tmp/err$readme_n"))" test $rc -eq 0
  check "  no nan: $cmd" bash -c '! grep -qiw nan "$1" "$2"' _ "$last_out" "$tmp/err$readme_n"
  out=$(sed -n 's/.*--out \([^ ]*\).*/\1/p' <<<"$cmd")
  if [[ "$cmd" == *"hybridwalk walk"* ]]; then
    check "  summary line first: $(head -1 "$last_out")" \
      grep -qE '^[^ ]+, [0-9]+ frames: (([0-9]+|<1) % warped|none warped \(.+\))' <(head -1 "$last_out")
    check "  index.html beside report.json" test -s "$clone/$out/index.html" -a -s "$clone/$out/report.json"
  fi
  if [[ "$cmd" == *"hybridwalk sweep"* ]]; then
    check "  the sweep names its pipeline" grep -q "runs of the default pipeline" "$last_out"
    check "  its page too" grep -q "the default pipeline" "$clone/$out/index.html"
  fi
}

# A summary value of a walk's report.json: readme_summary DIR PYTHON_EXPR (s = the summary).
readme_summary() {
  python3 -c 'import json,sys; s = json.load(open(sys.argv[1]))["summary"]; print(eval(sys.argv[2]))' \
    "$(readme_file "$1/report.json")" "$2" 2>/dev/null || echo none
}

readme_left_clean() {
  # Every file git does not track, ignored or not, must be under out/.
  local stray
  stray=$(git -C "$clone" ls-files --others | grep -v '^out/' | head -5 | tr '\n' ' ')
  check "  nothing left outside out/ (${stray:-none})" test -z "$stray"
  check "  out/ is ignored" git -C "$clone" check-ignore -q out/x
  check "  git status is clean but for out/" \
    bash -c 'test -z "$(git -C "$1" status --porcelain --untracked-files=all | grep "^??")"' _ "$clone"
}

readme_file() {
  local f
  for f in "$tmp"/clone.*/"$1"; do [ -e "$f" ] && { echo "$f"; return; }; done
  echo "$tmp/none/$1"
}
