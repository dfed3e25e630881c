#!/bin/sh
# MPMDEM_RSH_AGENT inside a SLURM allocation (scripts/slurm/column_collapse.sbatch): scripts/run
# calls `srun_agent.sh NODE COMMAND...` as it would call ssh, to start a DEM job's mpirun on
# its node (one dem_app job per DEM node: Open MPI 4.1, docs/cluster.md). The command line runs
# as one job step on NODE that shares the allocation (--overlap, Slurm >= 20.11) and gets the
# node's cores (MPMDEM_SRUN_CPUS, default SLURM_CPUS_ON_NODE). Stopping this srun (scripts/run
# does, by PID) makes SLURM end the step's processes on the node.
set -eu
host=${1:?usage: srun_agent.sh NODE COMMAND...}
shift
exec srun --overlap --nodes=1 --ntasks=1 --cpus-per-task="${MPMDEM_SRUN_CPUS:-${SLURM_CPUS_ON_NODE:-1}}" \
  --nodelist="$host" --kill-on-bad-exit=1 sh -c "$*"
