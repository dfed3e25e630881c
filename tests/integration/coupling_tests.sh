#!/usr/bin/env bash
# Two-process coupling tests (registered by coupling.cmake). Usage: coupling_tests.sh CASE
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
# Every process started (ompi-server, both mpiruns) is stopped by PID in a trap; each case
# also asserts that the programs ended by themselves within a bound, with the expected exit
# codes and messages.
set -uo pipefail
case_name=${1:?usage: coupling_tests.sh CASE}
bin=${MPMDEM_BIN:?set MPMDEM_BIN to the build directory}
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=../../scripts/lib/pair.sh
source "$src/scripts/lib/pair.sh"

dem_app=$bin/dem_app/dem_app
mpm_app=$bin/mpm_app/mpm_app
client=$bin/tests/rve_test_client
work=$bin/test-runs/coupling_$case_name
rm -rf "$work"
mkdir -p "$work/run"
cd "$work" || exit 1
pair_init

failures=0
fail() {
  echo "FAIL: $*" >&2
  failures=$((failures + 1))
}
expect_rc() {  # what got expected
  if [[ "$2" != "$3" ]]; then fail "$1 exited with $2, expected $3"; else echo "ok: $1 exited with $2"; fi
}
expect_in() {  # file pattern description
  if grep -qE -- "$2" "$1"; then echo "ok: $3"; else
    fail "$3: /$2/ not found in $1:"
    sed 's/^/    | /' "$1" >&2
  fi
}
expect_no_process_left() {
  # Every program of this case has $work in its command line (run dir, scene, URI file).
  local left i
  for i in 1 2 3 4 5 6 7 8 9 10; do  # log tees end right after their writer
    left=$(pgrep -f -- "$work/" | grep -vx "$$" | grep -vx "${PAIR_PIDS[0]:-none}" || true)
    [[ -z $left ]] && break
    sleep 0.2
  done
  if [[ -n $left ]]; then
    fail "processes still alive after the programs should have ended: $(echo $left)"
    ps -o pid,args -p $left >&2 || true
  else
    echo "ok: no process left"
  fi
}
expect_within() {  # seconds-taken limit what
  if (($1 > $2)); then fail "$3 took $1 s (limit $2 s)"; else echo "ok: $3 took $1 s (<= $2 s)"; fi
}

# A scene holding only what dem_app and the test client read: config_version + coupling.
write_scene() {  # file youngs_modulus [service]
  cat >"$1" <<YAML
config_version: 1
coupling:
  backend: elastic
  outputs: []
  service_name: ${3:-mpmdem_test}
  port_file: dem_port.txt
  connect_timeout_s: 30
  elastic:
    youngs_modulus: $2
    poisson_ratio: 0.3
YAML
}

run_client_pair() {  # ranks n steps extra-client-args...
  local ranks=$1 n=$2 steps=$3
  shift 3
  pair_start_ompi_server "$work" || exit 1
  pair_start_server "$ranks" "$work/server.log" "$dem_app" --backend elastic --scene scene.yaml \
    --run-dir "$work/run" "${server_extra[@]}"
  pair_start_client 1 "$work/client.log" "$client" --scene scene.yaml --run-dir "$work/run" \
    --n "$n" --steps "$steps" "$@"
  client_rc=0
  pair_wait_client || client_rc=$?
  server_rc=0
  pair_wait_server 20 || server_rc=$?
}

server_extra=()
case $case_name in
  client_elastic_1rank | client_elastic_2ranks)
    # Every reply equals the local elastic law; 11 RVEs over 2 ranks = partitions 6 + 5.
    write_scene scene.yaml 1.0e7
    ranks=1
    [[ $case_name == *2ranks ]] && ranks=2
    run_client_pair $ranks 11 6
    expect_rc "client" "$client_rc" 0
    expect_rc "dem_app" "$server_rc" 0
    expect_in client.log "worst relative stress error 0$" "replies equal the local law"
    expect_in server.log "serving 11 RVEs on $ranks rank" "server saw the client's RVE count"
    [[ -e run/dem_port.txt ]] && fail "port file not removed after accept"
    ;;
  client_checkpoint_restore)
    # Checkpoint after step 3 of 6, then a new server restores it and the client resumes.
    write_scene scene.yaml 2.0e7
    run_client_pair 2 9 6 --checkpoint-at 3
    expect_rc "client (first run)" "$client_rc" 0
    expect_rc "dem_app (first run)" "$server_rc" 0
    pair_cleanup
    server_extra=(--restore "$work/run/ckpt")
    run_client_pair 2 9 6 --resume 3
    expect_rc "client (resumed)" "$client_rc" 0
    expect_rc "dem_app (restored)" "$server_rc" 0
    expect_in client.log "steps 4..6, worst relative stress error 0$" "resumed stresses equal the law"
    ;;
  client_abort)
    write_scene scene.yaml 1.0e7
    run_client_pair 2 5 6 --abort-after 2
    expect_rc "client" "$client_rc" 0
    expect_rc "dem_app" "$server_rc" 4
    expect_in server.log "mpm_app aborted the run: rve_test_client: test abort" "server names the abort"
    ;;
  client_backend_error)
    # A failing backend (restore from a missing checkpoint) is reported to the client as a
    # PeerError naming rank and reason; the client aborts and both end non-zero.
    write_scene scene.yaml 1.0e7
    server_extra=(--restore "$work/no_such_checkpoint")
    run_client_pair 2 6 4 --resume 1
    expect_rc "client" "$client_rc" 4
    expect_rc "dem_app" "$server_rc" 4
    expect_in client.log "DEM server rank 0 failed during step: backend error.*no elastic checkpoint" \
      "client names the rank and the backend's reason"
    expect_in server.log "mpm_app aborted the run" "server reports the abort"
    ;;
  killed_client)
    # The client is killed (SIGKILL) mid-run: Open MPI does not tell the server, whose
    # --idle-timeout ends it with a message instead of a hang.
    write_scene scene.yaml 1.0e7
    pair_start_ompi_server "$work" || exit 1
    pair_start_server 2 "$work/server.log" "$dem_app" --backend elastic --scene scene.yaml \
      --run-dir "$work/run" --idle-timeout 3
    pair_start_client 1 "$work/client.log" "$client" --scene scene.yaml --run-dir "$work/run" \
      --n 50 --steps 100000000
    for i in $(seq 1 100); do grep -q "connected;" server.log 2>/dev/null && break; sleep 0.1; done
    sleep 0.5
    rank=$(pgrep -P "$PAIR_CLIENT_PID" -x rve_test_client)
    [[ -n $rank ]] || fail "client rank not found"
    start=$SECONDS
    kill -KILL $rank
    server_rc=0
    pair_wait_server 30 || server_rc=$?
    # The idle watchdog ends it (exit 4, with the reason), or a rank's MPI call fails on the
    # dead peer first (exit 4, with the MPI error), or Open MPI's runtime tears the connected
    # job down; never a hang (124: the harness had to kill it).
    if ((server_rc == 4)); then
      expect_in server.log "no message from mpm_app for 3 s \(--idle-timeout\)|rank [0-9]+: error: .*failed" \
        "server explains why it ends"
    elif ((server_rc == 0 || server_rc == 124)); then
      fail "dem_app exited with $server_rc after its client was killed"
      sed 's/^/    | /' server.log >&2
    else
      echo "ok: dem_app ended with $server_rc (torn down by the MPI runtime)"
    fi
    expect_within $((SECONDS - start)) 15 "the server's exit"
    ;;
  hash_mismatch)
    # The server reads a scene whose coupling section differs (another Young's modulus).
    write_scene scene.yaml 1.0e7
    write_scene other.yaml 3.0e7
    pair_start_ompi_server "$work" || exit 1
    start=$SECONDS
    pair_start_server 2 "$work/server.log" "$dem_app" --backend elastic --scene other.yaml \
      --run-dir "$work/run"
    pair_start_client 1 "$work/client.log" "$client" --scene scene.yaml --run-dir "$work/run"
    client_rc=0
    pair_wait_client || client_rc=$?
    server_rc=0
    pair_wait_server 20 || server_rc=$?
    expect_rc "client" "$client_rc" 3
    expect_rc "dem_app" "$server_rc" 3
    pattern="coupling section hash differs: rve_test_client 0x[0-9a-f]{16} \(scene.yaml\) vs dem_app 0x[0-9a-f]{16} \(other.yaml\)"
    expect_in client.log "$pattern" "client names both hashes and files"
    expect_in server.log "$pattern" "server names both hashes and files"
    expect_within $((SECONDS - start)) 30 "the refused handshake"
    expect_no_process_left
    ;;
  version_mismatch)
    # Test hook: the client claims protocol major version 99.
    write_scene scene.yaml 1.0e7
    pair_start_ompi_server "$work" || exit 1
    start=$SECONDS
    pair_start_server 1 "$work/server.log" "$dem_app" --backend elastic --scene scene.yaml \
      --run-dir "$work/run"
    MPMDEM_TEST_FAKE_VERSION_MAJOR=99 pair_start_client 1 "$work/client.log" "$client" \
      --scene scene.yaml --run-dir "$work/run"
    client_rc=0
    pair_wait_client || client_rc=$?
    server_rc=0
    pair_wait_server 20 || server_rc=$?
    expect_rc "client" "$client_rc" 3
    expect_rc "dem_app" "$server_rc" 3
    pattern="protocol major version differs: rve_test_client 99\.[0-9]+ .* vs dem_app [0-9]+\.[0-9]+"
    expect_in client.log "$pattern" "client names both versions"
    expect_in server.log "$pattern" "server names both versions"
    expect_within $((SECONDS - start)) 30 "the refused handshake"
    expect_no_process_left
    ;;
  no_server_client)
    # ompi-server is up, but no dem_app: the client gives up after its timeout (4 s).
    write_scene scene.yaml 1.0e7
    pair_start_ompi_server "$work" || exit 1
    start=$SECONDS
    pair_start_client 1 "$work/client.log" "$client" --scene scene.yaml --run-dir "$work/run" \
      --timeout 4
    client_rc=0
    pair_wait_client || client_rc=$?
    expect_rc "client" "$client_rc" 4
    expect_in client.log "no DEM server found within 4 s .*service 'mpmdem_test'.*dem_port.txt.*start dem_app first" \
      "client says no server was found, naming service, port file and timeout"
    expect_within $((SECONDS - start)) 20 "giving up"
    expect_no_process_left
    ;;
  no_client_server)
    # dem_app alone: its watchdog ends it after --timeout, removing the port file.
    write_scene scene.yaml 1.0e7
    pair_start_ompi_server "$work" || exit 1
    start=$SECONDS
    pair_start_server 2 "$work/server.log" "$dem_app" --backend elastic --scene scene.yaml \
      --run-dir "$work/run" --timeout 3
    server_rc=0
    pair_wait_server 30 || server_rc=$?
    expect_rc "dem_app" "$server_rc" 4
    expect_in server.log "no mpm_app connected within 3 s \(coupling.connect_timeout_s\)" \
      "server says no client connected"
    [[ -e run/dem_port.txt ]] && fail "port file left behind"
    expect_within $((SECONDS - start)) 25 "giving up"
    expect_no_process_left
    ;;
  swap_sides)
    # Issue 2, item 8: the elastic column with the local linear_elastic model and with
    # `remote` against dem_app --backend elastic on 1 and on 2 ranks gives the same
    # stresses (<= 1e-10 relative). The remote scene is made from the local one here (same
    # grid, points, solver; constitutive.model remote; coupling with the same E and nu), and
    # both are shortened to 0.1 s of simulated time.
    /usr/bin/python3 - "$src/configs/elastic_column.yaml" <<'PY' || exit 1
import sys, yaml
d = yaml.safe_load(open(sys.argv[1]))
d["solver"]["end_time"] = 0.1
yaml.safe_dump(d, open("local.yaml", "w"), sort_keys=False)
law = d["constitutive"]["linear_elastic"]
d["constitutive"] = {"model": "remote"}
d["coupling"] = {"backend": "elastic", "service_name": "mpmdem_swap",
                 "elastic": {"youngs_modulus": law["youngs_modulus"],
                             "poisson_ratio": law["poisson_ratio"]}}
yaml.safe_dump(d, open("remote.yaml", "w"), sort_keys=False)
PY
    start=$SECONDS
    local_rc=0
    "$mpm_app" local.yaml --out "$work/local" >local.log 2>&1 || local_rc=$?
    expect_rc "mpm_app (linear_elastic)" "$local_rc" 0
    pair_start_ompi_server "$work" || exit 1
    for ranks in 1 2; do
      pair_start_server $ranks "$work/server$ranks.log" "$dem_app" --backend elastic \
        --scene remote.yaml --run-dir "$work/remote$ranks"
      pair_start_client 1 "$work/client$ranks.log" "$mpm_app" remote.yaml --out "$work/remote$ranks"
      client_rc=0
      pair_wait_client || client_rc=$?
      server_rc=0
      pair_wait_server 20 || server_rc=$?
      expect_rc "mpm_app (remote, $ranks server rank(s))" "$client_rc" 0
      expect_rc "dem_app ($ranks rank(s))" "$server_rc" 0
      expect_in "server$ranks.log" "on $ranks rank\(s\)" "dem_app served on $ranks rank(s)"
    done
    /usr/bin/python3 - "$work/local" "$work/remote1" "$work/remote2" <<'PY' || fail "stresses differ"
import sys, h5py, numpy as np
def load(d):
    with h5py.File(d + "/final_state.h5", "r") as f:
        return f["id"][()], f["stress"][()], f.attrs["step"]
ids0, s0, n0 = load(sys.argv[1])
scale = np.abs(s0).max()
assert scale > 1e3, f"local stresses too small to compare ({scale} Pa)"
ok = True
for d in sys.argv[2:]:
    ids, s, n = load(d)
    same = (ids == ids0).all() and n == n0
    rel = np.abs(s - s0).max() / scale
    print(f"{d}: {len(ids)} points, {n} steps, max |stress - local| / max |local| = {rel:.3e}")
    ok = ok and same and rel <= 1e-10
sys.exit(0 if ok else 1)
PY
    expect_within $((SECONDS - start)) 240 "the three runs"
    ;;
  mpm_no_server)
    # mpm_app with constitutive.model remote and no dem_app: clear message, non-zero exit
    # within its timeout (coupling.connect_timeout_s set to 4 s).
    sed -E 's/^(\s*connect_timeout_s:).*/\1 4/' "$src/configs/elastic_column_remote.yaml" >remote.yaml
    pair_start_ompi_server "$work" || exit 1
    start=$SECONDS
    pair_start_client 1 "$work/client.log" "$mpm_app" remote.yaml --out "$work/run"
    client_rc=0
    pair_wait_client || client_rc=$?
    if ((client_rc == 0)); then fail "mpm_app exited with 0 without a server"; else echo "ok: mpm_app exited with $client_rc"; fi
    expect_in client.log "no DEM server found within 4 s .*service 'mpmdem'.*dem_port.txt" \
      "mpm_app says no server was found"
    expect_within $((SECONDS - start)) 25 "giving up"
    expect_no_process_left
    ;;
  mpm_hash_mismatch)
    # dem_app started with a scene whose coupling section differs: both refuse.
    cp "$src/configs/elastic_column_remote.yaml" remote.yaml
    sed -E 's/^(\s*youngs_modulus:).*/\1 2.0e7/' remote.yaml >other.yaml
    pair_start_ompi_server "$work" || exit 1
    start=$SECONDS
    pair_start_server 2 "$work/server.log" "$dem_app" --backend elastic --scene other.yaml \
      --run-dir "$work/run"
    pair_start_client 1 "$work/client.log" "$mpm_app" remote.yaml --out "$work/run"
    client_rc=0
    pair_wait_client || client_rc=$?
    server_rc=0
    pair_wait_server 20 || server_rc=$?
    if ((client_rc == 0)); then fail "mpm_app exited with 0 despite the mismatch"; else echo "ok: mpm_app exited with $client_rc"; fi
    expect_rc "dem_app" "$server_rc" 3
    pattern="coupling section hash differs: mpm_app 0x[0-9a-f]{16} \(.*remote.yaml\) vs dem_app 0x[0-9a-f]{16} \(other.yaml\)"
    expect_in client.log "$pattern" "mpm_app names both hashes"
    expect_in server.log "$pattern" "dem_app names both hashes"
    expect_within $((SECONDS - start)) 30 "the refused handshake"
    expect_no_process_left
    ;;
  *)
    echo "unknown case $case_name" >&2
    exit 2
    ;;
esac

if ((failures)); then
  echo "coupling_$case_name: $failures failure(s); logs in $work" >&2
  exit 1
fi
echo "coupling_$case_name: passed"
