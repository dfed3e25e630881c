#!/usr/bin/env bash
# scripts/aspect_ratio_study on one tiny scene (a = 1 from configs/column_collapse_mc.yaml,
# the shipped transfer): the generated column has H_i = L_i, the run is complete and ends by
# its duration (the at-rest stop is removed), and the table, the CSV and the figure are
# written; an unknown scheme exits non-zero naming it and runs nothing.
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
set -uo pipefail
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=common.sh
source "$src/tests/integration/common.sh"
test_workdir aspect_ratio_study
fail() { echo "FAIL: $*" >&2; exit 1; }
export MPM_APP=$bin/mpm_app/mpm_app

"$src/scripts/aspect_ratio_study" --out "$work/s" --aspect-ratios 1 --schemes shipped \
  --cfl-check none >"$work/s.log" 2>&1 || { tail -n 30 "$work/s.log" >&2; fail "study failed"; }
[[ -s $work/s/table.md && -s $work/s/aspect_ratio.png && -s $work/s/study.csv ]] ||
  fail "table.md, aspect_ratio.png or study.csv missing"
/usr/bin/python3 - "$work/s" <<'PY' || exit 1
import csv, json, sys
w = sys.argv[1]
rows = list(csv.DictReader(open(w + "/study.csv")))
assert len(rows) == 1, rows
r = rows[0]
assert float(r["a"]) == 1 and abs(float(r["H_i"]) - float(r["L_i"])) < 1e-9, r
s = json.load(open(w + "/runs/a1_shipped_cfl0.5/summary.json"))
assert s["status"] == "complete" and s["stop"]["reason"] == "duration", s["stop"]
assert abs(s["aspect_ratio"] - 1) < 1e-9, s["aspect_ratio"]
assert abs(float(r["dL_over_Li"]) - (s["runout_m"] - s["initial_length_m"]) / s["initial_length_m"]) < 1e-9
assert "| 1 | 0.55, 0.55 |" in open(w + "/table.md").read()
PY
if "$src/scripts/aspect_ratio_study" --out "$work/bad" --schemes nope >"$work/bad.log" 2>&1; then
  fail "an unknown scheme was accepted"
fi
grep -q "unknown scheme 'nope'" "$work/bad.log" || { cat "$work/bad.log" >&2; fail "no message"; }
[[ ! -d $work/bad/runs/a1_nope_cfl0.5 ]] || fail "ran something with a bad scheme"
echo "aspect_ratio_study smoke: ok"
