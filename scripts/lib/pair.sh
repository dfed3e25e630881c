# shellcheck shell=bash
# Launching the coupled pair (ompi-server, dem_app under mpirun, the client under mpirun)
# and stopping every process started, by PID, also on failure and Ctrl-C.
# Source it, then:
#   pair_init                                  # installs the cleanup trap
#   pair_start_ompi_server DIR                 # URI file DIR/ompi-server.uri
#   pair_start_server NP LOG dem_app ARGS...   # background, output to LOG; called once per
#                                              # DEM job (one per DEM host, docs/cluster.md)
#   pair_start_client NP LOG mpm_app ARGS...   # background, output to stdout and LOG
#   pair_start_local LOG mpm_app ARGS...       # mpm_app alone, without mpirun
#   pair_wait_client                           # exit code of the client's mpirun
#   pair_wait_client_watching_server GRACE     # same, stopping the client if a server job
#                                              # ended GRACE s before it (returns 4 then)
#   pair_wait_server SECONDS                   # exit code of the servers' mpiruns (the first
#                                              # non-zero one; 124: one had to be killed)
# Each process runs in its own session (setsid), so killing its process group also stops
# the MPI ranks that mpirun forked.

PAIR_PIDS=()
PAIR_URI=""
PAIR_SERVER_PID=""   # the last server job started
PAIR_SERVER_PIDS=() # every server job (one mpirun, or its launcher, per DEM job)
PAIR_CLIENT_PID=""
PAIR_CLIENT_LOCAL=0
PAIR_FINAL_HOOK=""  # function run after an interrupt's cleanup (e.g. print the results)
# Extra mpirun options per side, e.g. (--hostfile FILE) or (--host h1:4,h2:4): node partitions.
PAIR_SERVER_MPIRUN_ARGS=()
PAIR_CLIENT_MPIRUN_ARGS=()

# mpirun options for two separately launched jobs on one machine. Open MPI 4 needs the
# shared ompi-server for connect/accept; binding is off so that OpenMP threads and several
# ranks on few cores are not pinned to one core; idle ranks yield the CPU instead of
# spinning (measured on 2 cores, dem_app on 2 ranks + mpm_app: 30 ms per exchange without
# it, 3 ms with it).
# Both jobs run on this machine: keep Open MPI's TCP traffic (and its interface probing) on
# the loopback interface. Set MPMDEM_MPI_IF to another interface list for multi-host runs.
pair_mpirun_args() {
  local ifs=${MPMDEM_MPI_IF:-lo}
  local args=(--oversubscribe --bind-to none --mca mpi_yield_when_idle 1
    --mca btl_tcp_if_include "$ifs" --mca oob_tcp_if_include "$ifs"
    --ompi-server "file:$PAIR_URI")
  if [[ $(id -u) -eq 0 ]]; then args+=(--allow-run-as-root); fi
  # Another launcher than ssh for the hosts of --mpm-hosts/--dem-hosts (docs/cluster.md):
  # the orted stays a child of it (not daemonized), so stopping mpirun's process tree by
  # PID also stops the remote side when the agent's processes run on this machine.
  if [[ -n ${MPMDEM_RSH_AGENT:-} ]]; then
    args+=(--mca plm_rsh_agent "$MPMDEM_RSH_AGENT" --mca plm_rsh_no_tree_spawn 1 --leave-session-attached)
  fi
  if [[ -n "${OMP_NUM_THREADS:-}" ]]; then args+=(-x OMP_NUM_THREADS); fi
  args+=(${MPMDEM_MPIRUN_ARGS:-})
  printf '%s\n' "${args[@]}"
}

# Sleep SECONDS without starting a process: the watch loop below runs for the whole job,
# and a forked `sleep` costs ~8 ms of CPU here (measured with perf sched: 5 per second took
# 5 % of a core from the DEM ranks). read -t on a pipe nobody writes to just times out.
PAIR_NAP_FD=""
pair_nap() {
  if [[ -z $PAIR_NAP_FD ]]; then exec {PAIR_NAP_FD}<> <(:); fi
  read -r -t "$1" -u "$PAIR_NAP_FD" || true
}

# PIDs of every descendant of the given PIDs (mpirun puts its ranks in their own
# process groups, so a group kill alone would miss them).
pair_descendants() {
  local pid child
  for pid in "$@"; do
    for child in $(pgrep -P "$pid" 2>/dev/null); do
      echo "$child"
      pair_descendants "$child"
    done
  done
}

pair_cleanup() {
  ((${#PAIR_PIDS[@]})) || return 0
  local pid all
  all=("${PAIR_PIDS[@]}")
  mapfile -t -O ${#all[@]} all < <(pair_descendants "${PAIR_PIDS[@]}")
  for pid in "${PAIR_PIDS[@]}"; do
    if kill -0 "$pid" 2>/dev/null; then kill -TERM -- "-$pid" 2>/dev/null || kill -TERM "$pid" 2>/dev/null; fi
  done
  local t alive
  for t in $(seq 1 20); do
    alive=0
    for pid in "${all[@]}"; do
      if kill -0 "$pid" 2>/dev/null; then alive=1; fi
    done
    ((alive)) || break
    sleep 0.25
  done
  for pid in "${all[@]}"; do
    kill -KILL "$pid" 2>/dev/null || true
  done
  for pid in "${PAIR_PIDS[@]}"; do wait "$pid" 2>/dev/null || true; done
  PAIR_PIDS=()
  PAIR_SERVER_PIDS=()
  PAIR_SERVER_PID=""
  PAIR_CLIENT_PID=""
}

# Ctrl-C: let mpm_app stop in order first (it writes its summary and tells the server),
# then stop everything that is left.
pair_interrupt() {
  trap '' INT TERM
  echo "interrupted: stopping mpm_app, then every process started" >&2
  if [[ -n $PAIR_CLIENT_PID ]] && kill -0 "$PAIR_CLIENT_PID" 2>/dev/null; then
    if ((PAIR_CLIENT_LOCAL)); then
      kill -INT "$PAIR_CLIENT_PID" 2>/dev/null
    else
      local child
      for child in $(pgrep -P "$PAIR_CLIENT_PID"); do kill -INT "$child" 2>/dev/null; done
    fi
    local i
    for i in $(seq 1 100); do
      kill -0 "$PAIR_CLIENT_PID" 2>/dev/null || break
      sleep 0.1
    done
  fi
  pair_cleanup
  if [[ -n $PAIR_FINAL_HOOK ]]; then "$PAIR_FINAL_HOOK"; fi
  exit 130
}

pair_init() {
  trap 'pair_cleanup' EXIT
  trap 'pair_interrupt' INT TERM
}

pair_start_ompi_server() {
  local dir=$1
  PAIR_URI="$dir/ompi-server.uri"
  rm -f "$PAIR_URI"
  setsid ompi-server --no-daemonize --mca oob_tcp_if_include "${MPMDEM_MPI_IF:-lo}" -r "$PAIR_URI" </dev/null >"$dir/ompi-server.log" 2>&1 &
  PAIR_PIDS+=($!)
  local i
  for i in $(seq 1 100); do
    [[ -s "$PAIR_URI" ]] && return 0
    kill -0 "${PAIR_PIDS[-1]}" 2>/dev/null || break
    sleep 0.1
  done
  echo "error: ompi-server did not start (see $dir/ompi-server.log)" >&2
  return 1
}

# PAIR_SERVER_LAUNCH_HOST: start the server's mpirun itself on that host, through
# MPMDEM_RSH_AGENT (default ssh) as one shell command line, instead of on this one. Open MPI
# 4.1 connects two mpirun jobs only when the accepting ranks run on their mpirun's own node
# (docs/cluster.md).
PAIR_SERVER_LAUNCH_HOST=""
pair_start_server() {
  local np=$1 log=$2
  shift 2
  local args
  mapfile -t args < <(pair_mpirun_args)
  echo "mpirun ${args[*]} ${PAIR_SERVER_MPIRUN_ARGS[*]} -np $np $*" >"$log"
  if [[ -n $PAIR_SERVER_LAUNCH_HOST ]]; then
    local cmd
    cmd="cd $(printf '%q' "$PWD") && exec env"
    [[ -z ${OMP_NUM_THREADS:-} ]] || cmd+=" OMP_NUM_THREADS=$(printf '%q' "$OMP_NUM_THREADS")"
    cmd+=" $(printf '%q ' mpirun "${args[@]}" "${PAIR_SERVER_MPIRUN_ARGS[@]}" -np "$np" "$@")"
    echo "(started on $PAIR_SERVER_LAUNCH_HOST through ${MPMDEM_RSH_AGENT:-ssh})" >>"$log"
    setsid "${MPMDEM_RSH_AGENT:-ssh}" "$PAIR_SERVER_LAUNCH_HOST" "$cmd" </dev/null >>"$log" 2>&1 &
  else
    setsid mpirun "${args[@]}" "${PAIR_SERVER_MPIRUN_ARGS[@]}" -np "$np" "$@" </dev/null >>"$log" 2>&1 &
  fi
  PAIR_SERVER_PID=$!
  PAIR_PIDS+=("$PAIR_SERVER_PID")
  PAIR_SERVER_PIDS+=("$PAIR_SERVER_PID")
}

pair_start_client() {
  local np=$1 log=$2
  shift 2
  local args
  mapfile -t args < <(pair_mpirun_args)
  # tee ignores Ctrl-C so that the client's last lines still reach the log.
  echo "mpirun ${args[*]} ${PAIR_CLIENT_MPIRUN_ARGS[*]} -np $np $*" >"$log.cmd"
  setsid mpirun "${args[@]}" "${PAIR_CLIENT_MPIRUN_ARGS[@]}" -np "$np" "$@" </dev/null > >(trap '' INT; exec tee "$log") 2>&1 &
  PAIR_CLIENT_PID=$!
  PAIR_CLIENT_LOCAL=0
  PAIR_PIDS+=("$PAIR_CLIENT_PID")
}

pair_start_local() {
  local log=$1
  shift
  setsid "$@" </dev/null > >(trap '' INT; exec tee "$log") 2>&1 &
  PAIR_CLIENT_PID=$!
  PAIR_CLIENT_LOCAL=1
  PAIR_PIDS+=("$PAIR_CLIENT_PID")
}

pair_wait_client() {
  local rc=0
  wait "$PAIR_CLIENT_PID" || rc=$?
  return $rc
}

# A server whose mpirun ended while the client still runs has lost a rank (or failed): the
# client detects a dead rank on this host itself within a second and ends with its fault
# checkpoint; this is the backstop for ranks it cannot probe (other hosts), bounded by GRACE.
pair_wait_client_watching_server() {
  local grace=$1 lost_at="" pid
  while kill -0 "$PAIR_CLIENT_PID" 2>/dev/null; do
    if [[ -z $lost_at ]]; then
      for pid in "${PAIR_SERVER_PIDS[@]}"; do kill -0 "$pid" 2>/dev/null || lost_at=$SECONDS; done
    fi
    if [[ -n $lost_at ]] && ((SECONDS - lost_at >= grace)); then
      echo "error: a DEM server job's mpirun ended, and mpm_app was still running $grace s later: stopped it" >&2
      kill -TERM -- "-$PAIR_CLIENT_PID" 2>/dev/null || kill -TERM "$PAIR_CLIENT_PID" 2>/dev/null
      local i
      for i in $(seq 1 50); do
        kill -0 "$PAIR_CLIENT_PID" 2>/dev/null || break
        sleep 0.1
      done
      kill -KILL -- "-$PAIR_CLIENT_PID" 2>/dev/null
      wait "$PAIR_CLIENT_PID" 2>/dev/null
      return 4
    fi
    pair_nap 0.5
  done
  local rc=0
  wait "$PAIR_CLIENT_PID" || rc=$?
  return $rc
}

# Wait up to SECONDS for the servers' mpiruns (all of them together); returns the first
# non-zero exit code, or 124 if one had to be killed. mpirun relays TERM to its daemons; one
# on a host it can no longer reach (a cut link) never answers, so the jobs still running get
# TERM together, 5 s later they and their processes on this machine get KILL.
pair_wait_server() {
  local seconds=$1 i pid alive rc=0 one
  for i in $(seq 1 $((seconds * 10))); do
    alive=0
    for pid in "${PAIR_SERVER_PIDS[@]}"; do kill -0 "$pid" 2>/dev/null && alive=1; done
    ((alive)) || break
    sleep 0.1
  done
  local late=() all=()
  for pid in "${PAIR_SERVER_PIDS[@]}"; do
    kill -0 "$pid" 2>/dev/null || continue
    late+=("$pid")
    mapfile -t -O ${#all[@]} all < <(pair_descendants "$pid")
    kill -TERM -- "-$pid" 2>/dev/null || true
  done
  if ((${#late[@]})); then
    for i in $(seq 1 50); do
      alive=0
      for pid in "${late[@]}"; do kill -0 "$pid" 2>/dev/null && alive=1; done
      ((alive)) || break
      sleep 0.1
    done
    for pid in "${late[@]}"; do
      kill -0 "$pid" 2>/dev/null || continue
      mapfile -t -O ${#all[@]} all < <(pair_descendants "$pid")
      kill -KILL -- "-$pid" 2>/dev/null
    done
    for i in "${all[@]}"; do kill -KILL "$i" 2>/dev/null; done
  fi
  for pid in "${PAIR_SERVER_PIDS[@]}"; do
    one=0
    wait "$pid" 2>/dev/null || one=$?
    if [[ " ${late[*]} " == *" $pid "* ]]; then one=124; fi
    ((rc != 0)) || rc=$one
  done
  return $rc
}
