#!/usr/bin/env bash
# A run that heals itself (issue 36, item 3). Hosts A, B, C, D are Linux network namespaces
# (netns_hosts.sh). As a user on host A would:
#   scripts/run SCENE --mpm-hosts A --dem-hosts B:1,C:1,D:1 --on-fault resume
# with the elastic column (multinode_scene.py elastic: a checkpoint every 100 steps,
# coupling.peer_timeout_s 3). Host C's link is cut right after the first complete
# checkpoint. Checks:
#   1. scripts/run ends with 0 by itself (no second command), the run complete, its end state
#      (final_state.h5: x, v, stress) equal bit for bit to the uninterrupted run's (the same
#      scene on this machine);
#   2. mpm_app named host C and its rank 1, within peer_timeout_s + 2 s of the cut;
#   3. summary.json "faults": one, host C, rank 1, the checkpoint resumed from (the newest
#      complete one at the fault) and a wall time lost; the run resumed from that step;
#   4. the second attempt ran on B and D only (2 jobs), the first attempt's logs are kept;
#   5. no process is left in any namespace (the namespaces are removed at the end, also on
#      failure).
# Needs root (ip netns, unshare --uts): without it the test exits 77 (CTest: skipped).
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
set -uo pipefail
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=common.sh
source "$src/tests/integration/common.sh"
# shellcheck source=netns_hosts.sh
source "$src/tests/integration/netns_hosts.sh"
netns_skip_unless_root
test_workdir multinode_heal
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
ok() { echo "ok: $*"; }
netns_make "mn$$" a b c d || { echo "FAIL: making the namespaces" >&2; exit 1; }
A=${HOST[a]} B=${HOST[b]} C=${HOST[c]} D=${HOST[d]}
echo "hosts: $A $B $C $D on $NET.0/24"
timeout_s=3

/usr/bin/python3 "$src/tests/integration/multinode_scene.py" elastic \
  "$src/configs/elastic_column_remote.yaml" "$work/scene.yaml" "mpmdem_multinode_heal_$$" || exit 1
grep -q "^  peer_timeout_s: $timeout_s\$" "$work/scene.yaml" || { echo "FAIL: scene edit" >&2; exit 1; }

# 0. The uninterrupted run, this machine.
run_job "$work/single.log" "$work/scene.yaml" --out "$work/single" --dem-ranks 3

# 1. A | B, C, D with --on-fault resume; C cut after the first complete checkpoint.
t0=$EPOCHREALTIME
on_host "$A" env MPMDEM_MPI_IF="$NET.0/24" MPMDEM_RSH_AGENT="$src/tests/integration/netns_agent.sh" \
  "$src/scripts/run" "$work/scene.yaml" --out "$work/heal" --mpm-hosts "$A" \
  --dem-hosts "$B:1,$C:1,$D:1" --on-fault resume >"$work/heal.log" 2>&1 &
run_pid=$!
cut=""
for _ in $(seq 1 1200); do
  if compgen -G "$work/heal/checkpoints/step_*/COMPLETE" >/dev/null; then
    netns_cut c && cut=$EPOCHREALTIME
    break
  fi
  kill -0 "$run_pid" 2>/dev/null || break
  sleep 0.05
done
[[ -n $cut ]] || { fail "no complete checkpoint to cut the link after"; tail -n 40 "$work/heal.log" >&2; exit 1; }
first=$(newest_checkpoint_step "$work/heal")
echo "cut host C's link after checkpoint step $first"
bound=90
for _ in $(seq 1 $((bound * 10))); do kill -0 "$run_pid" 2>/dev/null || break; sleep 0.1; done
if kill -0 "$run_pid" 2>/dev/null; then fail "scripts/run still running $bound s after the cut"; fi
rc=0
wait "$run_pid" || rc=$?
run_pid=""
took=$(/usr/bin/python3 -c "print(round($EPOCHREALTIME - $t0, 1))")
((rc == 0)) && ok "scripts/run healed and ended with 0 by itself ($took s in all)" ||
  { fail "scripts/run exited with $rc"; tail -n 40 "$work/heal.log" >&2; }

/usr/bin/python3 - "$work/single" "$work/heal" "$first" "$C" "$cut" "$timeout_s" <<'PY' || fail "end state or fault record"
import json, os, sys
import h5py, numpy as np
ref, run, first, host_c, cut, timeout_s = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4], float(sys.argv[5]), float(sys.argv[6])
s, r = json.load(open(ref + "/summary.json")), json.load(open(run + "/summary.json"))
assert s["status"] == r["status"] == "complete", (s["status"], r["status"])
assert s["steps"] == r["steps"], (s["steps"], r["steps"])
a, b = h5py.File(ref + "/final_state.h5"), h5py.File(run + "/final_state.h5")
assert a["stress"][:].reshape(-1, 9)[:, 8].min() < -1.0e4  # it settled under its weight
for k in ["x", "v", "stress"]:
    d = np.abs(a[k][:] - b[k][:]).max()
    assert d == 0.0, f"{k} differs from the uninterrupted run by {d}"
print(f"ok: {r['steps']} steps, x, v, stress equal to the uninterrupted run's bit for bit")
faults = r.get("faults")
assert faults and len(faults) == 1, faults
f = faults[0]
assert f["hosts"] == [host_c] and f["ranks"] == [1] and f["kind"] == "no_reply", f
assert f["checkpoint_step"] == first and f["checkpoint"].endswith("step_%09d" % first), (f, first)
assert r["resumed_from_step"] == first, r["resumed_from_step"]
assert f["step"] >= first and f["wall_time_lost_s"] > 0 and f["relaunch_s"] > 0 and f["redo_s"] > 0, f
detect = f["detected_at_epoch_s"] - cut
assert timeout_s <= detect + 0.5 and detect <= timeout_s + 2.0, f"detected {detect:.2f} s after the cut"
print(f"ok: summary.json faults: host C, rank 1, step {f['step']}, resumed from step {first}; "
      f"detected {detect:.2f} s after the cut; wall time lost {f['wall_time_lost_s']} s "
      f"(redo {f['redo_s']} s + relaunch {f['relaunch_s']} s)")
PY
grep -qE "no reply from DEM server rank 1 \(pid [0-9]+ on host $C\) within $timeout_s s \(coupling.peer_timeout_s\) during step [0-9]+ \(2 of 3 server ranks replied\): unreachable, hung or dead \(host $C: rank 1\)" \
  "$work/heal/logs/attempt1/mpm_app.log" && ok "mpm_app named host C and its rank: $(grep -o 'no reply from.*(host [^)]*)' "$work/heal/logs/attempt1/mpm_app.log")" ||
  fail "mpm_app did not name host C's rank (logs/attempt1/mpm_app.log)"
logs=$work/heal/logs
grep -qF "2 rank(s) in 2 jobs, 400 RVEs; on host $B rank 0, on host $D rank 1)" "$logs/mpm_app.log" &&
  [[ -f $logs/dem_app.job0.log && -f $logs/dem_app.job1.log && ! -e $logs/dem_app.job2.log ]] &&
  grep -q "(started on $B through" "$logs/dem_app.job0.log" && grep -q "(started on $D through" "$logs/dem_app.job1.log" &&
  ok "the second attempt ran on B and D (2 jobs); the first attempt's logs are in logs/attempt1/" ||
  { fail "the second attempt did not run on B and D alone"; grep connected "$logs/mpm_app.log" >&2; }
netns_no_process_left "after the healed run"

if ((failures)); then echo "multinode_heal: $failures failure(s)" >&2; exit 1; fi
echo "multinode_heal: passed"
