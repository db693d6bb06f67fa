# Shared by the tests/cli/*.sh tests (sourced, not a test itself):
#   hw = the program ($1), tmp = a scratch dir removed on exit,
#   check NAME COMMAND... counts a pass or prints "FAIL NAME",
#   finish prints "N passed, M failed" and fails the script on any failure.
set -u
hw=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
passed=0
check() {
  local name=$1; shift
  if "$@"; then passed=$((passed + 1)); else echo "FAIL $name"; failures=$((failures + 1)); fi
}
finish() {
  echo "$passed passed, $failures failed"
  [ "$failures" -eq 0 ]
}
