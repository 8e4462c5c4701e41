#!/usr/bin/python3
"""No function over 100 lines in the library (every folder of src/dba),
python/src/ and tools/. A function is counted from its signature's first
line to its closing brace at column 0 (the project's style; a function on
one line is not looked at); a declarative table of options (a function whose
name ends in Table or Options) is not counted.

    check_function_length.py ROOT
"""
import pathlib
import re
import sys

LIMIT = 100
OTHER_DIRS = ["python/src", "tools"]
SIGNATURE = re.compile(r"^[A-Za-z_][^;#]*\b(\w+)\s*\(")


def long_functions(path):
    lines = path.read_text().split("\n")
    i = 0
    while i < len(lines):
        m = SIGNATURE.match(lines[i])
        if m and not lines[i].startswith(("namespace", "using", "struct", "class", "enum", "template")):
            j = i
            while j < len(lines) and not lines[j].rstrip().endswith(("{", ";", "}")):
                j += 1
            if j < len(lines) and lines[j].rstrip().endswith("{"):
                k = j + 1
                while k < len(lines) and lines[k] != "}":
                    k += 1
                name = m.group(1)
                if k - i + 1 > LIMIT and not name.endswith(("Table", "Options")):
                    yield i + 1, k - i + 1, name
                i = k
        i += 1


def main():
    root = pathlib.Path(sys.argv[1])
    bad = 0
    library = sorted(str(p.relative_to(root)) for p in (root / "src/dba").iterdir() if p.is_dir())
    for d in library + OTHER_DIRS:
        for path in sorted((root / d).glob("*.cc")):
            if path.name.endswith("_test.cc"):
                continue
            for line, n, name in long_functions(path):
                print(f"{path}:{line}: {name} has {n} lines (at most {LIMIT})")
                bad += 1
    print("FAIL: functions over the limit (above)" if bad else "ok: no function over the limit")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
