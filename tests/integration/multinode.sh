#!/usr/bin/env bash
# DEM on several nodes (issue 36, items 1-2). Hosts A, B, C, D are Linux network namespaces
# (netns_hosts.sh). As a user on host A would:
#   scripts/run SCENE --mpm-hosts A --dem-hosts B:2,C:2,D:2 --max-steps 20
# starts one dem_app job per DEM host (its mpirun on that host through netns_agent.sh, its 2
# ranks there) and mpm_app (on A) joins the three jobs into one DEM partition of 6 ranks.
# The scene is the default 3D column (1,560 native RVEs), cheap to start (multinode_scene.py
# column), with the load balance on, so RVEs migrate between the jobs. Checks:
#   1. the end state (final_state.h5: x, v, stress) equals, bit for bit, the same scene on
#      6 DEM ranks of one job on this machine;
#   2. each DEM host ran its ranks: its job's log shows its mpirun started there with its
#      ranks, and both ranks' step counts; the ranks themselves reported their hosts to
#      mpm_app (RankIdentity: B ranks 0-1, C 2-3, D 4-5); RVEs migrated (load balance);
#   3. --mpm-hosts naming another host than scripts/run's is refused (exit 2, saying why);
#   4. no process is left in any namespace, which are removed at the end (also on failure).
# Needs root (ip netns, unshare --uts): without it the test exits 77 (CTest: skipped).
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
set -uo pipefail
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=common.sh
source "$src/tests/integration/common.sh"
# shellcheck source=netns_hosts.sh
source "$src/tests/integration/netns_hosts.sh"
netns_skip_unless_root
test_workdir multinode
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
ok() { echo "ok: $*"; }
netns_make "mn$$" a b c d || { echo "FAIL: making the namespaces" >&2; exit 1; }
A=${HOST[a]} B=${HOST[b]} C=${HOST[c]} D=${HOST[d]}
echo "hosts: $A $B $C $D on $NET.0/24"
steps=20

/usr/bin/python3 "$src/tests/integration/multinode_scene.py" column \
  "$src/configs/column_collapse_3d.yaml" "$work/scene.yaml" "mpmdem_multinode_$$" || exit 1

# 0. The reference: 6 DEM ranks, one job, this machine.
run_job "$work/single.log" "$work/scene.yaml" --out "$work/single" --dem-ranks 6 --max-steps $steps

# 1. mpm_app on A, one DEM job of 2 ranks on each of B, C and D.
t0=$EPOCHREALTIME
if on_host "$A" env MPMDEM_MPI_IF="$NET.0/24" MPMDEM_RSH_AGENT="$src/tests/integration/netns_agent.sh" \
  "$src/scripts/run" "$work/scene.yaml" --out "$work/hosts" --max-steps $steps \
  --mpm-hosts "$A" --dem-hosts "$B:2,$C:2,$D:2" >"$work/hosts.log" 2>&1; then
  ok "scripts/run on A | B, C, D finished ($(/usr/bin/python3 -c "print(round($EPOCHREALTIME - $t0, 1))") s)"
else
  fail "scripts/run on A | B, C, D failed"
  tail -n 40 "$work/hosts.log" >&2
fi
/usr/bin/python3 - "$work/single" "$work/hosts" $steps <<'PY' || fail "end state"
import json, sys
import h5py, numpy as np
ref, run, steps = sys.argv[1], sys.argv[2], int(sys.argv[3])
s, r = json.load(open(ref + "/summary.json")), json.load(open(run + "/summary.json"))
assert s["status"] == r["status"] == "truncated", (s["status"], r["status"])
assert s["steps"] == r["steps"] == steps, (s["steps"], r["steps"])
a, b = h5py.File(ref + "/final_state.h5"), h5py.File(run + "/final_state.h5")
# Not a trivial state: the column has moved and carries stress.
assert np.abs(a["v"][:]).max() > 1e-3 and np.abs(a["stress"][:]).max() > 10.0
for k in ["x", "v", "stress"]:
    d = np.abs(a[k][:] - b[k][:]).max()
    assert d == 0.0, f"{k} differs from the one-host run by {d}"
print(f"ok: after {steps} steps x, v, stress of the 3-host run equal the one-host run's bit for bit")
PY
logs=$work/hosts/logs
k=0
for h in "$B" "$C" "$D"; do
  log=$logs/dem_app.job$k.log
  r0=$((2 * k)) r1=$((2 * k + 1))
  if grep -q "(started on $h through" "$log" && grep -q -- "--host $h:2 -np 2 .* --jobs 3 --job-index $k\$" "$log" &&
    [[ $(grep -cE "^dem_app: timing rank ($r0|$r1): $steps steps" "$log") == 2 ]]; then
    ok "host $h ran DEM job $k: its mpirun there, ranks $r0 and $r1 each $steps steps ($(basename "$log"))"
  else
    fail "host $h: $(basename "$log") does not show job $k's mpirun there with ranks $r0, $r1 of $steps steps"
    cat "$log" >&2
  fi
  k=$((k + 1))
done
grep -qF "6 rank(s) in 3 jobs, 1560 RVEs; on host $B ranks 0-1, on host $C ranks 2-3, on host $D ranks 4-5)" "$logs/mpm_app.log" &&
  ok "the ranks reported their hosts: $(grep -o 'on host .*' "$logs/mpm_app.log" | head -1)" ||
  { fail "mpm_app does not see ranks 0-1 on B, 2-3 on C, 4-5 on D"; grep connected "$logs/mpm_app.log" >&2; }
moves=$(grep -c "load balance: RVEs moved between the 6 DEM ranks" "$logs/mpm_app.log")
((moves >= 1)) && ok "$moves load-balance migration(s) across the jobs" || fail "no load-balance migration"
netns_no_process_left "after the run on 4 hosts"

# 3. mpm_app's host must be scripts/run's: B from A is refused before anything starts.
on_host "$A" env MPMDEM_MPI_IF="$NET.0/24" "$src/scripts/run" "$work/scene.yaml" --out "$work/refused" \
  --mpm-hosts "$B" --dem-hosts "$C:2" >"$work/refused.log" 2>&1
rc=$?
((rc == 2)) && grep -q "mpm_app would run on '$B', but its mpirun runs where scripts/run runs ($A).*orte_rml_base_parse_uris" "$work/refused.log" &&
  [[ ! -e $work/refused ]] && ok "--mpm-hosts $B from $A refused (exit 2, naming the crash)" ||
  { fail "--mpm-hosts $B from $A: exit $rc"; cat "$work/refused.log" >&2; }

if ((failures)); then echo "multinode: $failures failure(s)" >&2; exit 1; fi
echo "multinode: passed"
