#!/usr/bin/env bash
# element_test against a real dem_app (registered by element_test.cmake).
# Usage: element_test.sh CASE      CASE: elastic_oedometric | elastic_triaxial | yade_triaxial
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
# Every process started (ompi-server, both mpiruns) is stopped by PID in a trap (pair.sh).
set -uo pipefail
case_name=${1:?usage: element_test.sh CASE}
bin=${MPMDEM_BIN:?set MPMDEM_BIN to the build directory}
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=../../scripts/lib/pair.sh
source "$src/scripts/lib/pair.sh"

dem_app=$bin/dem_app/dem_app
driver=$bin/dem_app/element_test
work=$bin/test-runs/element_test_$case_name
rm -rf "$work"
mkdir -p "$work/run"
cd "$work" || exit 1
pair_init

run_pair() {  # backend ranks driver-args...
  local backend=$1 ranks=$2
  shift 2
  pair_start_ompi_server "$work" || exit 1
  pair_start_server "$ranks" "$work/server.log" "$dem_app" --backend "$backend" \
    --scene scene.yaml --run-dir "$work/run" --idle-timeout 60
  pair_start_client 1 "$work/client.log" "$driver" --scene scene.yaml --run-dir "$work/run" \
    --out "$work/out.csv" "$@"
  client_rc=0
  pair_wait_client || client_rc=$?
  server_rc=0
  pair_wait_server 30 || server_rc=$?
  if [[ $client_rc != 0 || $server_rc != 0 ]]; then
    echo "FAIL: element_test exited $client_rc, dem_app exited $server_rc" >&2
    sed 's/^/    server| /' "$work/server.log" >&2
    exit 1
  fi
}

case $case_name in
  elastic_oedometric)
    E=2.0e7 nu=0.25 P=1.0e4 S=0.01 N=20
    cat >scene.yaml <<YAML
config_version: 1
coupling:
  backend: elastic
  outputs: []
  service_name: mpmdem_element_oedo
  port_file: dem_port.txt
  connect_timeout_s: 30
  elastic:
    youngs_modulus: $E
    poisson_ratio: $nu
YAML
    run_pair elastic 2 --test oedometric --rves 3 --strain $S --steps $N --pressure $P
    # Hencky: sigma_zz = -P + M log(1 - S), sigma_xx = sigma_yy = -P + lambda log(1 - S).
    /usr/bin/python3 - "$work/out.csv" $E $nu $P $S $N <<'PY' || exit 1
import csv, math, sys
path, E, nu, P, S, N = sys.argv[1], *map(float, sys.argv[2:6]), int(sys.argv[6])
lam = E * nu / ((1 + nu) * (1 - 2 * nu)); mu = E / (2 * (1 + nu)); M = lam + 2 * mu
rows = list(csv.DictReader(open(path)))
assert len(rows) == 3 * (N + 1), f"{len(rows)} rows, expected {3 * (N + 1)}"
worst = 0.0
for r in rows:
    assert int(r["status"]) == 0, r
    ez = float(r["eps_zz"])
    for key, want in (("sigma_zz", -P + M * ez), ("sigma_xx", -P + lam * ez), ("sigma_yy", -P + lam * ez)):
        got = float(r[key]); err = abs(got - want) / abs(want); worst = max(worst, err)
        assert err <= 1e-9, f"step {r['step']} rve {r['rve']} {key} {got} != {want} (rel {err})"
last = rows[-1]
ez = float(last["eps_zz"])
assert abs(ez - math.log(1 - S)) <= 1e-12, f"final eps_zz {ez} != log(1-S) {math.log(1 - S)}"
want = -P + M * math.log(1 - S)
print(f"ok: final sigma_zz {float(last['sigma_zz']):.12g} = -P + M log(1-S) = {want:.12g}; worst rel. error {worst:.2e}")
PY
    grep -q "non-zero statuses: 0$" client.log || { echo "FAIL: statuses" >&2; exit 1; }
    ;;
  elastic_triaxial)
    # The mixed control on an elastic solid: once converged, sigma_xx = sigma_yy = -P,
    # sigma_zz = -P + E eps_zz and eps_xx = -nu eps_zz (Hencky strains, coaxial path).
    E=2.0e7 nu=0.25 P=1.0e4 S=0.01 N=30
    cat >scene.yaml <<YAML
config_version: 1
coupling:
  backend: elastic
  outputs: []
  service_name: mpmdem_element_triax_el
  port_file: dem_port.txt
  connect_timeout_s: 30
  elastic:
    youngs_modulus: $E
    poisson_ratio: $nu
YAML
    run_pair elastic 2 --test triaxial --rves 2 --strain $S --steps $N --pressure $P
    /usr/bin/python3 - "$work/out.csv" $E $nu $P <<'PY' || exit 1
import csv, sys
path, E, nu, P = sys.argv[1], *map(float, sys.argv[2:5])
rows = list(csv.DictReader(open(path)))
for r in rows[-2:]:
    ez, ex = float(r["eps_zz"]), float(r["eps_xx"])
    checks = (("sigma_xx", float(r["sigma_xx"]), -P, 1e-4), ("sigma_yy", float(r["sigma_yy"]), -P, 1e-4),
              ("sigma_zz", float(r["sigma_zz"]), -P + E * ez, 1e-6), ("eps_xx", ex, -nu * ez, 1e-3))
    for name, got, want, tol in checks:
        assert abs(got - want) <= tol * abs(want), f"rve {r['rve']} {name} {got} != {want} (tol {tol})"
    print(f"ok: rve {r['rve']}: sigma_xx {float(r['sigma_xx']):.8g}, sigma_zz {float(r['sigma_zz']):.10g} "
          f"= -P + E eps_zz {-P + E * ez:.10g}, eps_xx/eps_zz {ex / ez:.6f}")
PY
    ;;
  yade_triaxial)
    P=1.0e4 N=24
    cat >scene.yaml <<YAML
config_version: 1
coupling:
  backend: yade
  outputs: []
  service_name: mpmdem_element_triax
  port_file: dem_port.txt
  connect_timeout_s: 60
  yade:
    inline_spheres: 40
    ns_rule: fixed
    ns: 10
YAML
    run_pair yade 2 --test triaxial --rves 2 --strain 0.006 --steps $N --pressure $P
    /usr/bin/python3 - "$work/out.csv" $P $N <<'PY' || exit 1
import csv, sys
path, P, N = sys.argv[1], float(sys.argv[2]), int(sys.argv[3])
rows = list(csv.DictReader(open(path)))
assert len(rows) == 2 * (N + 1), f"{len(rows)} rows, expected {2 * (N + 1)}"
for r in rows:
    assert int(r["status"]) == 0, f"status {r['status']} at step {r['step']} rve {r['rve']}"
for k in (0, 1):
    mine = [r for r in rows if int(r["rve"]) == k]
    p0 = float(mine[0]["p"])
    assert p0 > 0 and abs(p0 - P) <= 0.2 * P, f"RVE {k}: p after initialise {p0}, expected {P} +- 20%"
    q = [float(r["q"]) for r in mine]
    ez = [float(r["eps_zz"]) for r in mine]
    assert ez[-1] < ez[0], f"RVE {k}: no axial compression"
    half = mine[N // 2 :]
    q_late = sum(float(r["q"]) for r in half) / len(half)
    assert q_late > 1.5 * q[0], f"RVE {k}: q did not grow with axial strain: {q}"
    # Mixed control: lateral stresses held near -P over the second half of the path.
    lat = sum(-(float(r["sigma_xx"]) + float(r["sigma_yy"])) / 2 for r in half) / len(half)
    assert abs(lat - P) <= 0.25 * P, f"RVE {k}: mean lateral stress {lat}, expected {P} +- 25%"
    print(f"ok: RVE {k}: p0 = {p0:.4g} Pa, q {q[0]:.4g} -> mean {q_late:.4g} Pa (2nd half), "
          f"lateral {lat:.4g} Pa, eps_zz {ez[-1]:.4g}")
PY
    grep -q "non-zero statuses: 0$" client.log || { echo "FAIL: statuses" >&2; exit 1; }
    ;;
  *)
    echo "unknown case $case_name" >&2
    exit 2
    ;;
esac
echo "PASS: $case_name"
