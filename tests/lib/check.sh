# Shared by the end-to-end test scripts: a scratch directory removed at exit,
# pass/fail counting, and the closing "N passed, M failed" line.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
passes=0
failures=0
check() {  # check NAME COMMAND...
  local name=$1
  shift
  if "$@"; then
    passes=$((passes + 1))
  else
    echo "FAILED: $name" >&2
    failures=$((failures + 1))
  fi
}
contains() { grep -qF -- "$2" "$1"; }
lacks() { ! grep -qF -- "$2" "$1"; }
finish() {
  echo "$passes passed, $failures failed"
  test "$failures" -eq 0
}
source "$(dirname "${BASH_SOURCE[0]}")/need_shared.sh"
source "$(dirname "${BASH_SOURCE[0]}")/json.sh"
