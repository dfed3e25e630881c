#!/usr/bin/env bash
# mpm_app against `dem_app --backend BACKEND` (yade or native, the first argument) on 2 ranks
# on a tiny scene (tests/integration/<BACKEND>_block_tiny.yaml). Checks: both exit 0, the run
# is complete, mass is conserved exactly, and every RVE's vertical stress is the geostatic rho*g*depth of its
# point within 10% (the RVEs start consolidated to it and the block stays at rest).
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir). Every process started is stopped by
# PID in pair.sh's trap.
set -uo pipefail
backend=${1:?usage: mpm_block.sh yade|native}
bin=${MPMDEM_BIN:?set MPMDEM_BIN to the build directory}
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=../../scripts/lib/pair.sh
source "$src/scripts/lib/pair.sh"

work=$bin/test-runs/mpm_$backend
rm -rf "$work"
mkdir -p "$work/run"
cd "$work" || exit 1
cp "$src/tests/integration/${backend}_block_tiny.yaml" scene.yaml
pair_init
pair_start_ompi_server "$work" || exit 1
pair_start_server 2 "$work/server.log" "$bin/dem_app/dem_app" --backend "$backend" --scene scene.yaml \
  --run-dir "$work/run" --idle-timeout 120
pair_start_client 1 "$work/client.log" "$bin/mpm_app/mpm_app" scene.yaml --out "$work/run" \
  --threads 1
client_rc=0
pair_wait_client || client_rc=$?
server_rc=0
pair_wait_server 30 || server_rc=$?
if [[ $client_rc != 0 || $server_rc != 0 ]]; then
  echo "FAIL: mpm_app exited $client_rc, dem_app exited $server_rc" >&2
  sed 's/^/    client| /' "$work/client.log" >&2
  sed 's/^/    server| /' "$work/server.log" >&2
  exit 1
fi
/usr/bin/python3 - "$work/run" <<'PY'
import json, sys
import h5py, numpy as np
run = sys.argv[1]
s = json.load(open(run + "/summary.json"))
assert s["status"] == "complete", s["status"]
assert abs(s["mass_grid_kg"] - s["mass_initial_kg"]) <= 1e-12 * s["mass_initial_kg"], (s["mass_initial_kg"], s["mass_grid_kg"])
f = h5py.File(run + "/final_state.h5", "r")
sigma, x0 = f["stress"][:], f["x0"][:]
assert np.all(np.isfinite(sigma))
rho, g, top = 1500.0, 9.81, 0.5
expected = -rho * g * (top - x0[:, 2])
err = np.abs(sigma[:, 2, 2] - expected) / np.abs(expected)
print("sigma_zz", sigma[:, 2, 2].round(1), "expected", expected.round(1), "max rel err", err.max())
assert err.max() < 0.10, err.max()
assert np.all(np.linalg.eigvalsh(0.5 * (sigma + sigma.transpose(0, 2, 1))) < 0), "not compressive"
print("PASS")
PY
