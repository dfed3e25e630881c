#!/usr/bin/env bash
# scripts/element_seed_study's pieces that need no DEM run (scripts/lib/element_seeds.py):
# the statistics on known numbers, the reseeded config (same packing item, new seed and name,
# both backends' packing lists), the summary over seeds from synthetic compare.json files
# (mean, standard error), and a config it cannot reseed (exit 2 naming the key and the file).
set -uo pipefail
src=${MPMDEM_SRC:?}
py=/usr/bin/python3
lib=$src/scripts/lib/element_seeds.py
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$py" "$lib" --self-test || fail "self-test"

"$py" "$lib" config "$src/configs/element_test/table1_dense.yaml" 7 "$work/s7.yaml" || fail "config"
"$py" - "$work/s7.yaml" <<'PY' || fail "reseeded config"
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
items = c["packings"]["items"]
assert items == [{"name": "table1_dense", "protocol": "dense", "seed": 7}], items
assert c["coupling"]["yade"]["packings"] == ["table1_dense_s7"], c["coupling"]["yade"]
assert c["packings"]["pressure"] in (1e5, "1.0e5"), c["packings"]
print("reseeded config: ok")
PY

# Two seeds with differences +1 and -0.5 deg: mean +0.25, standard error 0.75.
for s in 1 2; do
  mkdir -p "$work/study/seed_$s"
  d=$([[ $s == 1 ]] && echo 1.0 || echo -0.5)
  n=$([[ $s == 1 ]] && echo 31.0 || echo 29.5)
  cat >"$work/study/seed_$s/compare.json" <<JSON
{"backends": ["yade", "native"], "criterion_deg": 1.5, "packings": ["p_s$s"],
 "tests": {"triaxial": {
   "phi_peak_deg": {"yade": 30.0, "native": $n, "difference": $d},
   "phi_cs_deg": {"yade": 20.0, "native": 20.0, "difference": 0.0}}}}
JSON
done
"$py" "$lib" summary "$work/study" 1 2 >"$work/summary.log" || fail "summary"
"$py" - "$work/study/seeds.json" <<'PY' || fail "summary statistics"
import json, sys
d = json.load(open(sys.argv[1]))["paths"]["triaxial"]["phi_peak_deg"]
assert abs(d["mean_difference"] - 0.25) < 1e-12 and abs(d["standard_error"] - 0.75) < 1e-12, d
assert abs(d["mean_yade"] - 30.0) < 1e-12 and abs(d["mean_native"] - 30.25) < 1e-12, d
print("summary: ok")
PY

# A config whose packing no item of its packings: block builds: nothing to reseed.
sed 's/packings: \[quick_s4\]/packings: [other_s1]/' "$src/configs/element_test/quick.yaml" \
  >"$work/quick.yaml"
"$py" "$lib" config "$work/quick.yaml" 3 "$work/q.yaml" 2>"$work/err.log"
rc=$?
[[ $rc == 2 ]] || fail "unseedable config: exit $rc, expected 2"
grep -q "coupling.yade.packings\[0\] = 'other_s1'" "$work/err.log" &&
  grep -q "$work/quick.yaml" "$work/err.log" ||
  fail "message does not name the key and the file: $(cat "$work/err.log")"
[[ ! -e $work/q.yaml ]] || fail "a config was written for an unseedable input"
echo "element_seeds: all checks passed"
