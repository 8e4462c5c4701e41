#!/usr/bin/env bash
# A reader of the repository has no issue tracker: comments, docs, tests and
# scripts cite docs/ or a section of bench/README.md, never an issue number.
# Fails on any tracked file (or, outside a git checkout, any file) naming
# one, and lists each line. Usage: check_no_issue_references.sh PROJECT_ROOT
set -uo pipefail
root=$1
# Spelt with a bracket so that this file does not match itself.
pattern='\b[Ii]ssues?[[:space:]]+#?[0-9]{1,4}\b'
if git -C "$root" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  found=$(git -C "$root" grep -nIE "$pattern" -- . || true)
else
  found=$(grep -rnIE --exclude-dir=build "$pattern" "$root" || true)
fi
if [ -n "$found" ]; then
  echo "issue numbers cited (cite docs/ or bench/README.md instead):" >&2
  echo "$found" >&2
  exit 1
fi
echo "no issue numbers cited"
