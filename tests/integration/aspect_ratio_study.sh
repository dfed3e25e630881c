#!/usr/bin/env bash
# scripts/aspect_ratio_study on one tiny scene (a = 1 from configs/column_collapse_mc.yaml,
# the shipped transfer): the generated column has H_i = L_i, the run is complete and ends by
# its duration (the at-rest stop is removed), and the table (naming the scene's transfer from
# its solver keys), the CSV and the figure are written; the domain holds twice the law's
# runout, or --domain-factor times it; an unknown scheme or a factor below 1 exits non-zero
# naming it and runs nothing.
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
table = open(w + "/table.md").read()
assert "| 1 | 0.55, 0.55 |" in table
# the scene's transfer is named from its solver keys (configs/column_collapse_mc.yaml)
assert "the scene's: flip_velocity_scale 1.75" in table, table
# the domain holds twice the law's runout by default: 0.55 (1 + 2 x 1.2) = 1.87 m
import yaml
assert abs(yaml.safe_load(open(w + "/runs/a1_shipped_cfl0.5.yaml"))["grid"]["extent"][0] - 1.87) < 1e-9
PY
# --domain-factor 3: 0.55 (1 + 3 x 1.2) = 2.53 m; a factor below 1 is refused
"$src/scripts/aspect_ratio_study" --out "$work/f3" --aspect-ratios 1 --schemes shipped \
  --cfl-check none --domain-factor 3 >"$work/f3.log" 2>&1 ||
  { tail -n 30 "$work/f3.log" >&2; fail "study with --domain-factor 3 failed"; }
/usr/bin/python3 -c "
import sys, yaml
x = yaml.safe_load(open(sys.argv[1]))['grid']['extent'][0]
assert abs(x - 2.53) < 1e-9, x" "$work/f3/runs/a1_shipped_cfl0.5.yaml" || fail "--domain-factor 3"
if "$src/scripts/aspect_ratio_study" --out "$work/f0" --domain-factor 0.5 >"$work/f0.log" 2>&1; then
  fail "--domain-factor 0.5 was accepted"
fi
grep -q "domain-factor '0.5' is not a number >= 1" "$work/f0.log" || { cat "$work/f0.log" >&2; fail "no message"; }

if "$src/scripts/aspect_ratio_study" --out "$work/bad" --schemes nope >"$work/bad.log" 2>&1; then
  fail "an unknown scheme was accepted"
fi
grep -q "unknown scheme 'nope'" "$work/bad.log" || { cat "$work/bad.log" >&2; fail "no message"; }
[[ ! -d $work/bad/runs/a1_nope_cfl0.5 ]] || fail "ran something with a bad scheme"
echo "aspect_ratio_study smoke: ok"
