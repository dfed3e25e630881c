#!/usr/bin/env bash
# mpm_app against `dem_app --backend cuda` with coupling.cuda.device: host (the GPU backend's
# batch code on the CPU) on 2 server ranks, and the same scene on the native backend
# (tests/integration/native_block_tiny.yaml): both complete, and the final stresses, positions
# and RVE outputs of the two runs are the same bits. Then device: gpu on this host without a
# GPU: dem_app refuses it, naming coupling.cuda.device: host. Env: MPMDEM_BIN, MPMDEM_SRC.
set -uo pipefail
bin=${MPMDEM_BIN:?set MPMDEM_BIN to the build directory}
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=../../scripts/lib/pair.sh
source "$src/scripts/lib/pair.sh"

run_pair() {  # BACKEND NAME: runs the scene NAME.yaml of the work folder
  local backend=$1 name=$2
  pair_init
  pair_start_ompi_server "$work/$name" || return 1
  pair_start_server 2 "$work/$name/server.log" "$bin/dem_app/dem_app" --backend "$backend" \
    --scene "$name.yaml" --run-dir "$work/$name/run" --idle-timeout 120
  pair_start_client 1 "$work/$name/client.log" "$bin/mpm_app/mpm_app" "$name.yaml" \
    --out "$work/$name/run" --threads 1
  local client_rc=0 server_rc=0
  pair_wait_client || client_rc=$?
  pair_wait_server 30 || server_rc=$?
  if [[ $client_rc != 0 || $server_rc != 0 ]]; then
    echo "FAIL ($name): mpm_app exited $client_rc, dem_app exited $server_rc" >&2
    sed 's/^/    client| /' "$work/$name/client.log" >&2
    sed 's/^/    server| /' "$work/$name/server.log" >&2
    return 1
  fi
}

work=$bin/test-runs/mpm_cuda
rm -rf "$work"
mkdir -p "$work/native/run" "$work/cuda/run" "$work/gpu/run"
cd "$work" || exit 1
cp "$src/tests/integration/native_block_tiny.yaml" native.yaml
/usr/bin/python3 - <<'PY'
import yaml
for name, device in (("cuda", "host"), ("gpu", "gpu")):
    d = yaml.safe_load(open("native.yaml"))
    d["coupling"]["backend"] = "cuda"
    d["coupling"]["cuda"] = {"device": device}
    yaml.safe_dump(d, open(name + ".yaml", "w"), sort_keys=False)
PY
grep -q "backend: cuda" cuda.yaml || { echo "FAIL: cuda.yaml not made" >&2; exit 1; }
run_pair native native || exit 1
run_pair cuda cuda || exit 1
grep -q "cuda backend on the host" cuda/server.log || {
  echo "FAIL: the cuda run's server log does not name the cuda backend" >&2
  exit 1
}
/usr/bin/python3 - "$work/native/run" "$work/cuda/run" <<'PY'
import json, sys
import h5py, numpy as np
a, b = sys.argv[1], sys.argv[2]
for run in (a, b):
    assert json.load(open(run + "/summary.json"))["status"] == "complete"
fa, fb = h5py.File(a + "/final_state.h5", "r"), h5py.File(b + "/final_state.h5", "r")
names = [n for n in fa if isinstance(fa[n], h5py.Dataset)]
assert "stress" in names and "x" in names, names
for n in names:
    x, y = fa[n][()], fb[n][()]
    assert x.shape == y.shape and x.tobytes() == y.tobytes(), (n, np.max(np.abs(x - y)))
print("native and cuda (device: host) runs: %d final_state datasets equal bit for bit" % len(names))
PY
[[ $? == 0 ]] || exit 1
# device: gpu on a host without a GPU (or a build without CUDA): a clear refusal.
if command -v nvidia-smi >/dev/null && nvidia-smi -L >/dev/null 2>&1; then
  echo "PASS (a GPU is visible: the refusal is not checked)"
  exit 0
fi
run_pair cuda gpu 2>"$work/gpu.err" && { echo "FAIL: device: gpu accepted without a GPU" >&2; exit 1; }
cat "$work/gpu/server.log" "$work/gpu/client.log" | grep -q "set coupling.cuda.device: host" || {
  echo "FAIL: the refusal does not name coupling.cuda.device: host" >&2
  sed 's/^/    client| /' "$work/gpu/client.log" >&2
  exit 1
}
echo "PASS"
