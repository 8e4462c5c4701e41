# Sourced by the end-to-end test scripts.
# need_shared PATH...: the shared data the script reads (../shared/data beside
# the repository); a missing one fails the script at once, naming it.
need_shared() {
  local missing=0
  for p in "$@"; do
    if [ ! -e "$p" ]; then
      echo "FAILED: missing $p (the shared data, ../shared/data beside the repository)" >&2
      missing=1
    fi
  done
  if [ "$missing" -ne 0 ]; then
    echo "0 passed, 1 failed"
    exit 1
  fi
}
