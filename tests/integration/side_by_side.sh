#!/usr/bin/env bash
# Side by side (issue 3, item 7): the stresses dem_app --backend yade returns over MPI for a
# given dF sequence equal, to round-off, those of a standalone YADE script doing the same in
# one process (tests/integration/yade_standalone.py): the coupling adds no error.
# Registered by side_by_side.cmake. Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
#  1. scripts/build_packings: one 40-sphere Table 1 packing (loose, towards 10 kPa) into the work dir;
#  2. a seeded sequence of 12 increments dF (stretch, shear and rotation, |dF - I| ~ 1e-3);
#  3. dem_app on 2 ranks serving 2 RVEs that both load the packing, driven by element_test
#     --test df_file --pressure 0 (zero initial stress: no consolidation, the packing as built);
#  4. the standalone script on the same packing and dF's, same ns and damping;
#  5. every RVE's stress at every step equals the standalone one to <= 1e-10 relative (to the
#     largest stress component), and the client's strain log(V) of prod dF equals the
#     standalone cell's to <= 1e-12.
# Every process started (ompi-server, both mpiruns) is stopped by PID in a trap (pair.sh).
set -uo pipefail
bin=${MPMDEM_BIN:?set MPMDEM_BIN to the build directory}
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=../../scripts/lib/pair.sh
source "$src/scripts/lib/pair.sh"
export OMP_NUM_THREADS=1
NS=10 DAMPING=0.2 STEPS=12
work=$bin/test-runs/side_by_side
rm -rf "$work"
mkdir -p "$work/run" "$work/packings"
cd "$work" || exit 1
pair_init

cat >packings.yaml <<'YAML'
packings:            # a quick, small packing (not converged to 1e4 Pa: any contact network will do)
  n_spheres: 40
  pressure: 1.0e4
  protocol: loose
  porosity_init: 0.65
  max_strain_rate: 10.0
  stress_tol: 0.01
  unbalanced_tol: 0.05
  max_steps: 60000
  items:
    - {name: small, seed: 3}
YAML
"$src/scripts/build_packings" --config packings.yaml --out packings >build_packings.log 2>&1 ||
  { cat build_packings.log >&2; echo "FAIL: build_packings" >&2; exit 1; }
packing=$work/packings/small_s3.yade.bz2

/usr/bin/python3 - "$STEPS" >dF.txt <<'PY'
import math, random, sys
rng = random.Random(20261123)
print("# dF per step, row-major: stretch + shear + rotation, |dF - I| ~ 1e-3")
for n in range(int(sys.argv[1])):
    a = [[(1.0 if i == j else 0.0) + rng.uniform(-1e-3, 1e-3) for j in range(3)] for i in range(3)]
    t = rng.uniform(-2e-3, 2e-3)  # rotation about z on top
    c, s = math.cos(t), math.sin(t)
    R = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
    dF = [[sum(R[i][k] * a[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    print(" ".join(repr(dF[i][j]) for i in range(3) for j in range(3)))
PY

cat >scene.yaml <<YAML
config_version: 1
coupling:
  backend: yade
  outputs: []
  service_name: mpmdem_side_by_side
  port_file: dem_port.txt
  connect_timeout_s: 60
  yade:
    packing_dir: $work/packings
    packings: [small_s3]
    ns_rule: fixed
    ns: $NS
    damping: $DAMPING
    stiffness: none
    ke_threshold: 1.0e12  # p0 is 1 Pa for a zero initial stress: never flag "exploding" here
YAML
pair_start_ompi_server "$work" || exit 1
pair_start_server 2 "$work/server.log" "$bin/dem_app/dem_app" --backend yade \
  --scene scene.yaml --run-dir "$work/run" --idle-timeout 60
pair_start_client 1 "$work/client.log" "$bin/dem_app/element_test" --scene scene.yaml \
  --run-dir "$work/run" --out "$work/server.csv" --test df_file --df-file dF.txt \
  --rves 2 --steps $STEPS --pressure 0 --strain 0
client_rc=0
pair_wait_client || client_rc=$?
server_rc=0
pair_wait_server 30 || server_rc=$?
pair_cleanup
if [[ $client_rc != 0 || $server_rc != 0 ]]; then
  echo "FAIL: element_test exited $client_rc, dem_app exited $server_rc" >&2
  sed 's/^/    server| /' "$work/server.log" >&2
  exit 1
fi

/usr/bin/python3 "$src/tests/integration/yade_standalone.py" "$packing" dF.txt $NS $DAMPING \
  standalone.csv >standalone.log 2>&1 || { cat standalone.log >&2; echo "FAIL: standalone" >&2; exit 1; }
grep yade_standalone: standalone.log

/usr/bin/python3 - server.csv standalone.csv $STEPS <<'PY' || exit 1
import csv, sys
srv = list(csv.DictReader(open(sys.argv[1])))
ref = {int(r["step"]): r for r in csv.DictReader(open(sys.argv[2]))}
steps = int(sys.argv[3])
comps = ("xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz")
assert len(srv) == 2 * (steps + 1), f"{len(srv)} server rows, expected {2 * (steps + 1)}"
assert sorted(ref) == list(range(steps + 1)), "standalone rows missing"
worst_s = worst_e = 0.0
scale = max(abs(float(ref[0]["sigma_%d" % i])) for i in range(9))
assert scale > 100, f"standalone initial stress {scale} Pa: the packing carries no load"
for r in srv:
    n, k = int(r["step"]), int(r["rve"])
    assert int(r["status"]) == 0, f"status {r['status']} at step {n} rve {k}"
    R = ref[n]
    ss = [float(r["sigma_" + c]) for c in comps]
    rs = [float(R["sigma_%d" % i]) for i in range(9)]
    es = [float(r["eps_" + c]) for c in comps]
    re = [float(R["eps_%d" % i]) for i in range(9)]
    m = max(abs(x) for x in rs)
    err_s = max(abs(a - b) for a, b in zip(ss, rs)) / m
    err_e = max(abs(a - b) for a, b in zip(es, re))
    worst_s, worst_e = max(worst_s, err_s), max(worst_e, err_e)
    assert err_s <= 1e-10, f"step {n} RVE {k}: server stress {ss} != standalone {rs} (rel {err_s:.3g})"
    assert err_e <= 1e-12, f"step {n} RVE {k}: strain {es} != standalone cell {re} ({err_e:.3g})"
moved = max(abs(float(ref[steps]["sigma_%d" % i]) - float(ref[0]["sigma_%d" % i])) for i in range(9))
assert moved > 1e-3 * scale, f"stress changed by only {moved} Pa over the path: nothing was tested"
print(f"ok: {len(srv)} server rows (2 RVEs on 2 ranks x {steps + 1} steps) equal the standalone "
      f"YADE run: worst stress difference {worst_s:.3g} of max|sigma|, worst strain difference "
      f"{worst_e:.3g}; stress changed by {moved:.4g} Pa over the path")
PY
echo "PASS: side_by_side"
