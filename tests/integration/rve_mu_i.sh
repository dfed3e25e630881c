#!/usr/bin/env bash
# scripts/rve_mu_i_study (registered by element_test.cmake).
# Usage: rve_mu_i.sh steps | run
#   steps: scripts/lib/rve_mu_i.py without a DEM run: its self-test (dt for a nominal I, the
#          fit recovering a known mu(I), the angle of a triaxial stress), the config it writes
#          for an I, and the configs it refuses (exit 2 naming the key and the file, nothing
#          written).
#   run:   the study end to end on 4 of the column's RVEs (100 spheres, native backend, rate
#          rule; the packings built by YADE into the test's folder) at I = 0.003, 0.03, 0.3 in
#          steps of at most 1e-4 strain (updates of at least 2.5e-5 s), checked against the granular rheology's law: the friction rises with I
#          (GDR MiDi 2004; Jop et al. 2006), by ~8 deg from 0.003 to 0.3 in the full study
#          (docs/rve_rate.md), asserted > 3 deg; the measured I within a factor 0.6-1.2 of the
#          nominal (p rises from 5 to ~7 kPa in drained triaxial compression); with
#          --proportional 1.5e4:100 (the shipped column's rule) the extra run's I is the rule's
#          ~13 /s axial rate, ~0.03, whatever dt.
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir). Every process scripts/element_test
# starts is stopped by its PID (scripts/lib/pair.sh).
set -uo pipefail
case_name=${1:?usage: rve_mu_i.sh steps|run}
bin=${MPMDEM_BIN:?set MPMDEM_BIN to the build directory}
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
py=/usr/bin/python3
lib=$src/scripts/lib/rve_mu_i.py
cfg=$src/configs/element_test/column_grains_mu_i.yaml
work=$bin/test-runs/rve_mu_i_$case_name
rm -rf "$work"
mkdir -p "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
grain=(--grain-diameter 2.3e-3 --grain-density 2500)

case $case_name in
  steps)
    "$py" "$lib" --self-test || fail "self-test"
    step=$("$py" "$lib" config "$cfg" 0.01 "$work/I.yaml" "${grain[@]}") || fail "config"
    "$py" - "$work/I.yaml" $step <<'PY' || fail "the config for I = 0.01"
import math, sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
et, t = c["element_test"], c["element_test"]["tests"][0]
rate = -math.log(1 - float(t["strain"])) / (t["steps"] * et["dt"])
I = math.sqrt(3) * rate * 2.3e-3 / math.sqrt(float(et["pressure"]) / 2500)  # 5.0e3: a YAML 1.1 string
assert abs(I - 0.01) < 1e-12, I
assert abs(et["dt"] - float(sys.argv[2])) < 1e-5 * et["dt"], (et["dt"], sys.argv[2])
assert t["steps"] == int(sys.argv[3]), (t["steps"], sys.argv[3])
assert rate * et["dt"] <= 1.0001e-4, rate * et["dt"]   # at most 1e-4 strain per step (slow I)
assert c["coupling"]["service_name"].endswith("_I0.01"), c["coupling"]["service_name"]
print("config: ok")
PY
    # refused: a rule other than rate, two paths, a non-positive I
    sed 's/^    ns_rule: rate .*/    ns_rule: proportional/' "$cfg" >"$work/prop.yaml"
    sed 's/^    - {path: triaxial, .*}$/&\n    - {path: simple_shear, strain: 0.3, steps: 100}/' \
      "$cfg" >"$work/two.yaml"
    for bad in prop two neg; do
      input=$work/$bad.yaml i=0.01
      [[ $bad == neg ]] && input=$cfg i=-1
      rc=0
      "$py" "$lib" config "$input" "$i" "$work/out_$bad.yaml" "${grain[@]}" 2>"$work/err_$bad.log" || rc=$?
      [[ $rc == 2 ]] || fail "$bad: exit $rc, expected 2"
      [[ ! -e $work/out_$bad.yaml ]] || fail "$bad: a config was written"
      case $bad in
        prop) grep -q "coupling.yade.ns_rule" "$work/err_$bad.log" && grep -q "$input" "$work/err_$bad.log" ;;
        two) grep -q "element_test.tests" "$work/err_$bad.log" && grep -q "$input" "$work/err_$bad.log" ;;
        neg) grep -q "inertial number -1" "$work/err_$bad.log" ;;
      esac || fail "$bad: the message does not name the key and the file: $(cat "$work/err_$bad.log")"
    done
    echo "rve_mu_i steps: all checks passed"
    ;;
  run)
    cd "$work" || exit 1
    # 4 RVEs (the shipped file: 16)
    "$py" - "$cfg" "$work/small.yaml" <<'PY' || fail "small config"
import sys, yaml
c = yaml.safe_load(open(sys.argv[1]))
c["packings"]["items"][0]["copies"] = 4
c["coupling"]["yade"]["packings"] = ["col100_s%d" % i for i in range(1, 5)]
c["coupling"]["service_name"] = "mpmdem_test_rve_mu_i"
c["element_test"]["rves"] = 4
c["element_test"]["timeout_s"] = 120
yaml.safe_dump(c, open(sys.argv[2], "w"), sort_keys=False)
PY
    rc=0
    MPMDEM_BUILD=$bin "$src/scripts/rve_mu_i_study" "$work/small.yaml" \
      --inertial-numbers "0.003 0.03 0.3" --proportional 1.5e4:100 --out "$work/out" || rc=$?
    [[ $rc == 0 ]] || fail "scripts/rve_mu_i_study exited $rc"
    for f in mu_i.json mu_i.md mu_i.png; do [[ -s $work/out/$f ]] || fail "$f missing"; done
    "$py" - "$work/out/mu_i.json" <<'PY' || exit 1
import json, sys
d = json.load(open(sys.argv[1]))
runs = {r["run"]: r for r in d["runs"]}
assert sorted(runs) == ["I_0.003", "I_0.03", "I_0.3"], sorted(runs)
for name, r in runs.items():
    nominal = float(name[2:])
    assert 0.6 < r["inertial_number"] / nominal < 1.2, (name, r["inertial_number"])
    assert r["rves"] == 4, r
rise = runs["I_0.3"]["phi_deg"] - runs["I_0.003"]["phi_deg"]
print("phi %.2f / %.2f / %.2f deg at I %.3g / %.3g / %.3g" % tuple(
    [runs[k]["phi_deg"] for k in ("I_0.003", "I_0.03", "I_0.3")] +
    [runs[k]["inertial_number"] for k in ("I_0.003", "I_0.03", "I_0.3")]))
assert rise > 3.0, "friction rises %.2f deg from I = 0.003 to 0.3, expected > 3" % rise
assert d["fit"]["b"] > 0, d["fit"]
# the proportional rule (1.5e4:100, the shipped column's): 6.7e-5 strain per DEM substep of
# ~5.2e-6 s, ~13 /s axial whatever dt: I ~0.03 at ~7 kPa (0.0305 in the full study)
(p,) = d["proportional_runs"]
assert p["run"] == "proportional" and 0.015 < p["inertial_number"] < 0.06, p
print("proportional rule: I %.3g, phi %.2f deg" % (p["inertial_number"], p["phi_deg"]))
print("rve_mu_i run: ok")
PY
    ;;
  *) fail "unknown case $case_name" ;;
esac
