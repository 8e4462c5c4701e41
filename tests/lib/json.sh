# Reading dba's JSON reports in the end-to-end test scripts (python3's json).
# json FILE EXPR: true when the Python expression EXPR holds for the parsed
# report `d` (e.g. 'near(d["final_cost"], 125.1696, 1e-5)'); says why if not.
json() {
  python3 - "$1" "$2" <<'PY'
import json, sys
def near(a, b, rel):
    return abs(a - b) <= rel * abs(b)
try:
    with open(sys.argv[1]) as f:
        d = json.load(f)
    ok = eval("(" + sys.argv[2] + ")", {"d": d, "near": near, "abs": abs, "len": len, "all": all, "any": any})
except Exception as e:
    print(f"json {sys.argv[1]}: {type(e).__name__}: {e}", file=sys.stderr)
    sys.exit(1)
if not ok:
    print(f"json {sys.argv[1]}: not true: {sys.argv[2]}", file=sys.stderr)
sys.exit(0 if ok else 1)
PY
}
# json_value FILE KEY: a top-level value of a report, printed in full precision.
json_value() { python3 -c 'import json,sys; print(repr(json.load(open(sys.argv[1]))[sys.argv[2]]))' "$1" "$2"; }
