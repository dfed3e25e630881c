#!/usr/bin/env bash
# protocol_reference_client (registered by reference_client.cmake): the Python client written
# from docs/protocol.md alone (reference_client.py) drives `dem_app --backend elastic` on 2
# ranks through the handshake, kInitialise, kStep (one step past the law's series limit, one
# with kFlagQueryOnly/kFlagSkip), kRebalance, kCheckpoint and kShutdown, checking every
# stress against the closed-form law to 1e-13 relative. First its own canonical coupling text
# and hash must equal `dem_app --print-config-hash`. Every process started (ompi-server, both
# mpiruns) is stopped by PID in a trap (scripts/lib/pair.sh), also on failure.
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
set -uo pipefail
bin=${MPMDEM_BIN:?set MPMDEM_BIN to the build directory}
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=../../scripts/lib/pair.sh
source "$src/scripts/lib/pair.sh"
dem_app=$bin/dem_app/dem_app
client=$src/tests/integration/reference_client.py
work=$bin/test-runs/protocol_reference_client
rm -rf "$work"
mkdir -p "$work/run"
cd "$work" || exit 1
pair_init
fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# A scene that exercises the hash text rule: keys out of order, a backend section as written
# (1.0e7 stays 1.0e7), generic numbers normalised (3e1 -> 30, 1.0e-5 -> 1e-05), a string that
# needs quotes, a partly given map, absent keys with their defaults.
cat >scene.yaml <<'YAML'
config_version: 1
coupling:
  elastic:
    poisson_ratio: 0.3
    youngs_modulus: 1.0e7
  backend: elastic
  service_name: mpmdem_reference_client
  port_file: "ref port.txt"
  connect_timeout_s: 3e1
  peer_timeout_s: 0.5e2
  lazy_tolerance: 1.0e-5
  load_balance:
    threshold: 0.0
YAML

# The client's constants, struct layouts and generic coupling keys are the doc's tables.
/usr/bin/python3 "$client" --check-doc "$src/docs/protocol.md" || fail "docs/protocol.md and the client differ (above)"

# The doc's example of dem_app --print-config-hash is what dem_app prints.
example=configs/elastic_column_remote.yaml
sed -n "\|^\$ build/dem_app/dem_app --print-config-hash $example\$|{n;p;n;p;q}" "$src/docs/protocol.md" >hash.doc
(cd "$src" && "$dem_app" --print-config-hash "$example") >hash.example || fail "dem_app --print-config-hash $example exited with $?"
[[ -s hash.doc ]] || fail "docs/protocol.md has no example of dem_app --print-config-hash $example"
diff -u hash.doc hash.example || fail "docs/protocol.md's example of dem_app --print-config-hash differs from its output (above)"
# Every canonical text the page shows (they are all of that scene) is that output's line 2.
grep '^{backend:' "$src/docs/protocol.md" | sort -u | diff -u <(sed -n 2p hash.example) - ||
  fail "a canonical text shown in docs/protocol.md differs from dem_app's for $example (above)"
echo "ok: docs/protocol.md's example of dem_app --print-config-hash is its output"

"$dem_app" --print-config-hash scene.yaml >hash.dem_app || fail "dem_app --print-config-hash exited with $?"
/usr/bin/python3 "$client" --print-config-hash scene.yaml >hash.client || fail "reference_client.py --print-config-hash failed"
if ! diff -u hash.dem_app hash.client; then
  fail "the client's canonical coupling text or hash (from docs/protocol.md) differs from dem_app's (above)"
fi
echo "ok: config hash $(head -1 hash.client) equals dem_app --print-config-hash"

pair_start_ompi_server "$work" || exit 1
pair_start_server 2 "$work/server.log" "$dem_app" --backend elastic --scene scene.yaml \
  --run-dir "$work/run" --idle-timeout 30
start=$SECONDS
pair_start_client 1 "$work/client.log" /usr/bin/python3 "$client" --scene scene.yaml \
  --run-dir "$work/run" --n 11 --steps 6
client_rc=0
pair_wait_client || client_rc=$?
server_rc=0
pair_wait_server 20 || server_rc=$?
took=$((SECONDS - start))
[[ $client_rc == 0 ]] || { sed 's/^/    server | /' server.log >&2; fail "the client exited with $client_rc"; }
[[ $server_rc == 0 ]] || { sed 's/^/    server | /' server.log >&2; fail "dem_app exited with $server_rc"; }
grep -q "worst relative stress error" client.log || fail "the client did not report its stress check"
grep -q "shutdown after 6 steps and 1 load-balance migration" server.log ||
  { sed 's/^/    server | /' server.log >&2; fail "dem_app did not report 6 steps and 1 migration"; }
echo "ok: client and dem_app ended with 0 after $took s"
