#!/usr/bin/env bash
# Writes README.md's table of `dba solve`'s options from the option table
# (src/dba/session/solve_option_table.cc), between its two markers. Needs a
# build (build/python). The test SolveOptionTable.ReadmeHoldsTheTable fails
# when the README's table is not the one this writes.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHONPATH=build/python /usr/bin/python3 - <<'PY'
import re
import dba._dba as d
readme = open("README.md").read()
begin = "<!-- options: made from the option table by scripts/update-option-table.sh -->\n"
end = "<!-- end of options -->\n"
table = d.solve_options_markdown()
if begin not in readme:
    raise SystemExit("README.md has no options marker")
head, rest = readme.split(begin, 1)
_, tail = rest.split(end, 1)
open("README.md", "w").write(head + begin + table + end + tail)
PY
