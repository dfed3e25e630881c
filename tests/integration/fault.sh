#!/usr/bin/env bash
# A DEM server rank killed mid-run (issue 6, item 5), through scripts/run:
#   1. the elastic column, coupled to dem_app on 2 ranks, with checkpoints; once one
#      checkpoint is complete, DEM rank 1 gets SIGKILL;
#   2. scripts/run must end non-zero (4) within 30 s of the kill, mpm_app must name rank 1
#      (pid and host), write checkpoints/fault_step_<n>/mpm.h5 (without COMPLETE) and mark
#      summary.json failed; no process of the run may be left; scripts/run prints how to
#      resume;
#   3. scripts/run --resume continues from the newest complete checkpoint, and its end state
#      (final_state.h5: x, v, stress) equals an uninterrupted run's bit for bit.
# Usage: fault.sh elastic. Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
# scripts/run stops every process it starts by PID; this script kills its own scripts/run
# (by PID) on failure.
set -uo pipefail
case_name=${1:?usage: fault.sh elastic}
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=common.sh
source "$src/tests/integration/common.sh"
test_workdir "fault_$case_name"
run_pid=""
stop_run() { [[ -n $run_pid ]] && kill -TERM "$run_pid" 2>/dev/null && wait "$run_pid" 2>/dev/null; }
trap stop_run EXIT

failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
ok() { echo "ok: $*"; }

# The elastic column, shorter, with a checkpoint every 100 steps (~1800 steps in all).
sed -e 's/^  end_time: .*/  end_time: 0.22/' -e "s/^  service_name: .*/  service_name: mpmdem_fault_test/" \
  -e 's/^  energy_interval: .*/&\n  checkpoint_interval_steps: 100\n  checkpoints_kept: 3/' \
  "$src/configs/elastic_column_remote.yaml" >"$work/scene.yaml"
grep -q '^  checkpoint_interval_steps: 100' "$work/scene.yaml" || { echo "FAIL: scene edit" >&2; exit 1; }

# 1. Run, kill DEM rank 1 after the first complete checkpoint.
"$src/scripts/run" "$work/scene.yaml" --out "$work/killed" --dem-ranks 2 >"$work/killed.log" 2>&1 &
run_pid=$!
victim=""
for _ in $(seq 1 300); do
  if compgen -G "$work/killed/checkpoints/step_*/COMPLETE" >/dev/null; then
    for pid in $(pgrep -f -- "dem_app --backend elastic --scene $work/scene.yaml"); do
      [[ $(tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep -x 'OMPI_COMM_WORLD_RANK=1') ]] && victim=$pid
    done
    [[ -n $victim ]] && break
  fi
  kill -0 "$run_pid" 2>/dev/null || break
  sleep 0.1
done
[[ -n $victim ]] || { echo "FAIL: no complete checkpoint / no DEM rank 1 to kill" >&2; cat "$work/killed.log" >&2; exit 1; }
kill -KILL "$victim"
killed_at=$EPOCHREALTIME
echo "killed DEM rank 1 (pid $victim)"
rc=0
for _ in $(seq 1 600); do kill -0 "$run_pid" 2>/dev/null || break; sleep 0.1; done
if kill -0 "$run_pid" 2>/dev/null; then
  fail "scripts/run still running 60 s after the kill"
  stop_run
fi
wait "$run_pid" || rc=$?
run_pid=""
took=$(/usr/bin/python3 -c "print(round($EPOCHREALTIME - $killed_at, 2))")
((rc == 4)) && ok "scripts/run exited with 4" || fail "scripts/run exited with $rc, expected 4"
/usr/bin/python3 -c "import sys; sys.exit(0 if $took <= 30 else 1)" && ok "it ended $took s after the kill (<= 30 s)" ||
  fail "it ended $took s after the kill (> 30 s)"
# The kill lands during a step or, when the run has reached the next checkpoint by then,
# during that checkpoint's exchange; both name the rank, its pid and the exchange.
grep -qE "DEM server rank 1 \(pid $victim on host [^)]+\) died during (step|the checkpoint after step) [0-9]+" \
  "$work/killed.log" &&
  ok "mpm_app names rank 1 and its pid" || fail "no 'DEM server rank 1 (pid $victim ...) died' in the log"
grep -q "scripts/run --resume $work/killed" "$work/killed.log" && ok "scripts/run says how to resume" ||
  fail "scripts/run does not print how to resume"
left=$(pgrep -f -- "$work/" || true)
[[ -z $left ]] && ok "no process of the run left" || { fail "processes left: $left"; ps -o pid,args -p $left >&2; kill -KILL $left 2>/dev/null; }
fault_dirs=("$work"/killed/checkpoints/fault_step_*)
if [[ -f ${fault_dirs[0]}/mpm.h5 && ! -e ${fault_dirs[0]}/COMPLETE ]]; then
  ok "fault checkpoint ${fault_dirs[0]##*/}/mpm.h5 written, not marked COMPLETE"
else
  fail "no fault checkpoint (checkpoints/fault_step_*/mpm.h5 without COMPLETE)"
fi
/usr/bin/python3 - "$work/killed" <<'PY' || fail "summary.json of the killed run"
import json, sys
s = json.load(open(sys.argv[1] + "/summary.json"))
assert s["status"] == "failed", s["status"]
assert "DEM server rank 1" in s["error"], s["error"]
print("ok: summary.json status failed:", s["error"][:100])
PY
[[ -e $work/killed/final_state.h5 ]] && fail "the killed run left a final_state.h5 (half-written result presented as whole)"

# 2. Resume it (from its newest complete checkpoint), and run the same scene without
# interruption.
newest=$(newest_checkpoint_step "$work/killed")
run_job "$work/resumed.log" --resume "$work/killed" --dem-ranks 2
check_resumed "$work/killed" "$newest"
run_job "$work/full.log" "$work/scene.yaml" --out "$work/full" --dem-ranks 2
/usr/bin/python3 - "$work/full" "$work/killed" <<'PY' || fail "resumed end state differs"
import json, sys
import h5py, numpy as np
full, res = sys.argv[1], sys.argv[2]
s, r = json.load(open(full + "/summary.json")), json.load(open(res + "/summary.json"))
assert s["status"] == "complete" and r["status"] == "complete", (s["status"], r["status"])
assert r.get("error", "") == "", r["error"]
a, b = h5py.File(full + "/final_state.h5"), h5py.File(res + "/final_state.h5")
assert a.attrs["step"] == b.attrs["step"] == s["steps"], (a.attrs["step"], b.attrs["step"])
# Physics, not just equality: the column settled under its weight (sigma_zz < 0 at the base).
assert a["stress"][:].reshape(-1, 9)[:, 8].min() < -1.0e4
for k in ["x", "v", "stress"]:
    d = np.abs(a[k][:] - b[k][:]).max()
    assert d == 0.0, f"resumed {k} differs by {d}"
print(f"ok: resumed run ends at step {s['steps']} with x, v, stress identical to the uninterrupted run")
PY
left=$(pgrep -f -- "$work/" || true)
[[ -z $left ]] || { fail "processes left after the resumed runs: $left"; kill -KILL $left 2>/dev/null; }
if ((failures)); then echo "fault_$case_name: $failures failure(s)" >&2; exit 1; fi
echo "fault_$case_name: passed"
