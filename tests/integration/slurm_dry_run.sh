#!/usr/bin/env bash
# The SLURM batch script (scripts/slurm/column_collapse.sbatch), without SLURM: bash -n, then
# a dry run in a fake allocation of 3 nodes x 24 tasks (SLURM_* variables, an `scontrol`
# on PATH that expands the node list, and a stand-in scripts/run that records its command
# line). Checks the two hostfiles it writes and the scripts/run command it ends with.
# Env: MPMDEM_BIN (build dir), MPMDEM_SRC (source dir).
set -uo pipefail
src=${MPMDEM_SRC:-$(cd "$(dirname "$0")/../.." && pwd)}
# shellcheck source=common.sh
source "$src/tests/integration/common.sh"
test_workdir slurm_dry_run
batch=$src/scripts/slurm/column_collapse.sbatch
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
ok() { echo "ok: $*"; }

bash -n "$batch" && ok "bash -n $batch" || fail "bash -n $batch"

# The fake allocation: submit dir with a stand-in scripts/run, scontrol on PATH.
fake=$work/submit
mkdir -p "$fake/scripts" "$work/bin"
cat >"$fake/scripts/run" <<'STUB'
#!/usr/bin/env bash
printf '%s\n' "$@" >"$(dirname "$0")/../run_args.txt"
env | grep '^MPMDEM_' | sort >"$(dirname "$0")/../run_env.txt"
STUB
chmod +x "$fake/scripts/run"
cat >"$work/bin/scontrol" <<'STUB'
#!/usr/bin/env bash
[[ $1 == show && $2 == hostnames && $3 == "node[01-03]" ]] || { echo "scontrol stub: $*" >&2; exit 1; }
printf 'node01\nnode02\nnode03\n'
STUB
chmod +x "$work/bin/scontrol"
(
  cd "$fake" &&
    env -u MPMDEM_MPI_IF -u MPMDEM_SKIP_SETUP PATH="$work/bin:$PATH" SLURM_SUBMIT_DIR="$fake" \
      SLURM_JOB_NODELIST="node[01-03]" SLURM_JOB_ID=4242 SLURM_NTASKS_PER_NODE="24(x3)" \
      bash "$batch" "$src/configs/column_collapse_paper.yaml" --max-steps 10
) >"$work/batch.log" 2>&1 || { fail "the batch script failed"; cat "$work/batch.log" >&2; }
out=$fake/runs/column_collapse_paper-slurm-4242
[[ $(cat "$out/mpm.hosts" 2>/dev/null) == "node01 slots=1" ]] && ok "mpm.hosts: node01 slots=1" ||
  fail "mpm.hosts: '$(cat "$out/mpm.hosts" 2>/dev/null)'"
[[ $(cat "$out/dem.hosts" 2>/dev/null) == $'node02 slots=24\nnode03 slots=24' ]] && ok "dem.hosts: node02, node03 with 24 slots each" ||
  fail "dem.hosts: '$(cat "$out/dem.hosts" 2>/dev/null)'"
expect=("$src/configs/column_collapse_paper.yaml" --out "$out/run" --force --mpm-hosts "$out/mpm.hosts"
  --dem-hosts "$out/dem.hosts" --dem-ranks 48 --threads 24 --max-steps 10)
mapfile -t got <"$fake/run_args.txt" 2>/dev/null
[[ "${got[*]}" == "${expect[*]}" ]] && ok "scripts/run ${got[*]}" || fail "scripts/run got '${got[*]}', expected '${expect[*]}'"
grep -qx 'MPMDEM_MPI_IF=ib0' "$fake/run_env.txt" && grep -qx 'MPMDEM_SKIP_SETUP=1' "$fake/run_env.txt" &&
  grep -qx "MPMDEM_RSH_AGENT=$fake/scripts/slurm/srun_agent.sh" "$fake/run_env.txt" &&
  grep -qx 'MPMDEM_SRUN_CPUS=24' "$fake/run_env.txt" &&
  ok "MPMDEM_MPI_IF=ib0, MPMDEM_SKIP_SETUP=1, MPMDEM_RSH_AGENT=scripts/slurm/srun_agent.sh, MPMDEM_SRUN_CPUS=24" ||
  fail "environment: $(tr '\n' ' ' <"$fake/run_env.txt")"

# The agent that starts each DEM node's mpirun there: one srun step on that node (an `srun`
# stand-in records its arguments).
cat >"$work/bin/srun" <<'STUB'
#!/usr/bin/env bash
printf '%s\n' "$@" >"$SRUN_ARGS"
STUB
chmod +x "$work/bin/srun"
PATH="$work/bin:$PATH" SRUN_ARGS=$work/srun_args.txt MPMDEM_SRUN_CPUS=24 \
  "$src/scripts/slurm/srun_agent.sh" node02 "cd /x && exec env mpirun -np 24 dem_app" ||
  fail "srun_agent.sh failed"
mapfile -t got <"$work/srun_args.txt" 2>/dev/null
expect=(--overlap --nodes=1 --ntasks=1 --cpus-per-task=24 --nodelist=node02 --kill-on-bad-exit=1 sh -c
  "cd /x && exec env mpirun -np 24 dem_app")
[[ "${got[*]}" == "${expect[*]}" ]] && ok "srun_agent.sh node02 CMD: srun ${got[*]}" ||
  fail "srun_agent.sh ran srun '${got[*]}', expected '${expect[*]}'"

# The hostfiles it wrote against scripts/run's own checks. This machine is not node01, where
# the batch script (and so scripts/run and mpm_app's mpirun) would run: refused, saying why.
MPMDEM_MPI_IF=ib0 "$src/scripts/run" "$work/no_such_scene.yaml" --mpm-hosts "$out/mpm.hosts" \
  --dem-hosts "$out/dem.hosts" >"$work/hostcheck.log" 2>&1
rc=$?
((rc == 2)) && grep -q "mpm_app would run on 'node01', but its mpirun runs where scripts/run runs.*open-mpi/ompi#6818" "$work/hostcheck.log" &&
  ok "scripts/run off node01 refuses --mpm-hosts node01 (exit 2, naming the Open MPI crash)" ||
  { fail "--mpm-hosts node01 off node01: exit $rc"; cat "$work/hostcheck.log" >&2; }
# On node01 itself (here: this machine's name in mpm.hosts) both hostfiles pass: a missing
# --dem-hosts file would stop it with 2 before anything starts; it gets to the scene check.
printf '%s slots=1\n' "$(hostname)" >"$work/mpm_here.hosts"
MPMDEM_MPI_IF=ib0 "$src/scripts/run" "$work/no_such_scene.yaml" --mpm-hosts "$work/mpm_here.hosts" \
  --dem-hosts "$out/dem.hosts" >"$work/hostcheck.log" 2>&1
grep -q "scene file '$work/no_such_scene.yaml' not found" "$work/hostcheck.log" &&
  ok "scripts/run on the MPM node accepts the two hostfiles" || { fail "scripts/run refused the hostfiles"; cat "$work/hostcheck.log" >&2; }

if ((failures)); then echo "slurm_dry_run: $failures failure(s)" >&2; exit 1; fi
echo "slurm_dry_run: passed"
