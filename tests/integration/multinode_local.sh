#!/usr/bin/env bash
# The join of several DEM jobs (issue 36, item 1) without namespaces or root: the jobs on this
# machine (a host list may name a host more than once: one job per entry). Checks:
#   1. scripts/run --dem-hosts localhost:1,localhost:2 (2 jobs, 3 ranks, the elastic column
#      with the load balance on): the end state equals 3 ranks of one job bit for bit, RVEs
#      migrated between the jobs, each job's log shows its ranks' steps;
#   2. a job that never comes (2 joined, 1 started): mpm_app and the started job end with 4
#      within coupling.connect_timeout_s + 15 s, naming the missing job's port / giving up;
#   3. jobs started for 3 while mpm_app joins 2: refused on both sides (exit 4), naming both
#      counts;
#   4. malformed DEM host specs: refused by scripts/run before anything starts (exit 2).
# Every process is stopped by PID (pair.sh's trap). Env: MPMDEM_BIN, MPMDEM_SRC.
set -uo pipefail
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=common.sh
source "$src/tests/integration/common.sh"
test_workdir multinode_local
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
ok() { echo "ok: $*"; }

/usr/bin/python3 - "$src/configs/elastic_column_remote.yaml" "$work/scene.yaml" "mpmdem_mnlocal_$$" <<'PY' || exit 1
import sys, yaml
s = yaml.safe_load(open(sys.argv[1]))
s["solver"]["end_time"] = 0.02
s["coupling"].update(service_name=sys.argv[3], connect_timeout_s=3,
                     load_balance={"threshold": 0.01, "min_interval_steps": 10})
yaml.safe_dump(s, open(sys.argv[2], "w"), sort_keys=False)
PY

# 1. Two jobs against one.
run_job "$work/one.log" "$work/scene.yaml" --out "$work/one" --dem-ranks 3
run_job "$work/two.log" "$work/scene.yaml" --out "$work/two" --dem-hosts localhost:1,localhost:2
/usr/bin/python3 - "$work/one" "$work/two" <<'PY' || fail "2 jobs vs 1: end state"
import json, sys
import h5py, numpy as np
a, b = h5py.File(sys.argv[1] + "/final_state.h5"), h5py.File(sys.argv[2] + "/final_state.h5")
s = json.load(open(sys.argv[2] + "/summary.json"))
assert s["status"] == "complete" and np.abs(a["stress"][:]).max() > 1e3
for k in ["x", "v", "stress"]:
    assert np.array_equal(a[k][:], b[k][:]), f"{k} differs"
print(f"ok: 2 jobs (1 + 2 ranks) end bitwise equal to 1 job of 3 ranks after {s['steps']} steps")
PY
logs=$work/two/logs
steps=$(/usr/bin/python3 -c "import json; print(json.load(open('$work/two/summary.json'))['steps'])")
grep -q "3 rank(s) in 2 jobs" "$logs/mpm_app.log" && grep -q "load balance: RVEs moved between the 3 DEM ranks" "$logs/mpm_app.log" &&
  grep -q "^dem_app: timing rank 0: $steps steps" "$logs/dem_app.job0.log" &&
  [[ $(grep -cE "^dem_app: timing rank [12]: $steps steps" "$logs/dem_app.job1.log") == 2 ]] &&
  ok "mpm_app joined 2 jobs; rank 0 in job 0, ranks 1-2 in job 1 ran $steps steps; RVEs migrated" ||
  { fail "2 jobs: logs"; tail -n 5 "$logs"/*.log >&2; }

# Host specs scripts/run refuses before anything starts (exit 2, saying what to change).
refused() {
  local what=$1 expect=$2 rc=0
  shift 2
  "$src/scripts/run" "$work/scene.yaml" --out "$work/refused" "$@" >"$work/refused.log" 2>&1 || rc=$?
  ((rc == 2)) && [[ ! -e $work/refused ]] && grep -q -- "$expect" "$work/refused.log" && ok "refused: $what" ||
    { fail "$what: exit $rc"; cat "$work/refused.log" >&2; }
}
refused "slots on some hosts only" "give slots for every host or for none" --dem-hosts localhost:2,localhost
refused "--dem-ranks other than the slots' sum" "--dem-ranks 5 differs from the 3 slots" \
  --dem-hosts localhost:1,localhost:2 --dem-ranks 5
refused "fewer ranks than hosts" "1 DEM rank(s) for 2 DEM hosts" --dem-hosts localhost,localhost --dem-ranks 1

# 2 and 3 with pair.sh directly (scripts/run always starts matching jobs).
# shellcheck source=../../scripts/lib/pair.sh
source "$src/scripts/lib/pair.sh"
pair_init
# start_jobs DIR CLIENT_JOBS SERVER_JOBS STARTED: STARTED jobs of one rank each, told SERVER_JOBS;
# mpm_app told CLIENT_JOBS; returns mpm_app's exit code; sets server_rc.
start_jobs() {
  local dir=$1 cjobs=$2 sjobs=$3 started=$4 j rc=0
  mkdir -p "$dir"
  pair_start_ompi_server "$dir" || return 1
  for ((j = 0; j < started; j++)); do
    pair_start_server 1 "$dir/dem$j.log" "$MPMDEM_BIN/dem_app/dem_app" --backend elastic \
      --scene "$work/scene.yaml" --run-dir "$dir" --jobs "$sjobs" --job-index "$j"
  done
  pair_start_client 1 "$dir/mpm.log" "$MPMDEM_BIN/mpm_app/mpm_app" "$work/scene.yaml" --out "$dir" \
    --dem-jobs "$cjobs" >/dev/null
  pair_wait_client || rc=$?
  server_rc=0
  pair_wait_server 15 || server_rc=$?
  pair_cleanup
  return $rc
}
t0=$SECONDS
start_jobs "$work/missing" 2 2 1
rc=$?
took=$((SECONDS - t0))
((rc == 4 && server_rc == 4 && took <= 18)) && grep -q "no DEM server found within 3 s .*dem_port.job1.txt" "$work/missing/mpm.log" &&
  grep -q "mpm_app found no port of the next DEM job and gave up" "$work/missing/dem0.log" &&
  ok "a missing job: mpm_app and job 0 end with 4 in $took s, naming job 1's port file" ||
  { fail "a missing job: mpm_app $rc, job 0 $server_rc, $took s"; cat "$work/missing/mpm.log" "$work/missing/dem0.log" >&2; }
start_jobs "$work/count" 2 3 2
rc=$?
((rc == 4 && server_rc == 4)) && grep -q "joining DEM job 0 of 2 refused: a DEM rank was started for 3 jobs (dem_app --jobs), mpm_app joins 2" "$work/count/mpm.log" &&
  ok "jobs started for 3, mpm_app joining 2: refused on both sides (exit 4)" ||
  { fail "job count mismatch: mpm_app $rc, jobs $server_rc"; cat "$work/count/mpm.log" "$work/count/dem0.log" >&2; }

if ((failures)); then echo "multinode_local: $failures failure(s)" >&2; exit 1; fi
echo "multinode_local: passed"
