# shellcheck shell=bash
# Host specs of scripts/run (--mpm-hosts, --dem-hosts) and the DEM jobs made from them
# (docs/cluster.md). Source it, then:
#   hosts_entries OPT SPEC       one line "HOST SLOTS" per host of a hostfile or a list
#                                h1[:slots],h2[:slots] (SLOTS empty when not given);
#                                returns 2 with a message when SPEC is malformed
#   hosts_is_local HOST          true for this machine (localhost, its host names)
#   hosts_check_mpm SPEC         refuses (2) an MPM host that is not this machine
#   dem_jobs_plan SPEC RANKS DEFAULT   sets DEM_JOB_HOSTS / DEM_JOB_RANKS: one DEM job per
#                                host (RANKS: --dem-ranks or empty; DEFAULT: ranks per host)
# Open MPI 4.1.4 connects two mpirun jobs only when each job's ranks run on its own mpirun's
# node (open-mpi/ompi#6818): so one DEM job per DEM host, each started on its host, and
# mpm_app's mpirun where scripts/run runs.

hosts_entries() {
  local opt=$1 spec=$2 line host slots
  if [[ -f $spec ]]; then
    [[ -r $spec ]] || { echo "run: $opt $spec: hostfile not readable" >&2; return 2; }
    local n=0
    while IFS= read -r line || [[ -n $line ]]; do
      line=${line%%#*}
      read -r host rest <<<"$line" || true
      [[ -n $host ]] || continue
      slots=""
      if [[ " $rest " =~ \ slots=([0-9]+)\  ]]; then slots=${BASH_REMATCH[1]}; fi
      [[ $host =~ ^[A-Za-z0-9._-]+$ && $slots != 0 ]] ||
        { echo "run: $opt $spec: bad line '$line' (expected 'HOST [slots=N]')" >&2; return 2; }
      echo "$host $slots"
      n=$((n + 1))
    done <"$spec"
    ((n)) || { echo "run: $opt $spec: hostfile lists no host" >&2; return 2; }
  elif [[ $spec == */* || $spec == *.txt || $spec == *hostfile* || $spec == *.hosts ]]; then
    echo "run: $opt $spec: no such hostfile" >&2
    return 2
  elif [[ $spec =~ ^[A-Za-z0-9._-]+(:[1-9][0-9]*)?(,[A-Za-z0-9._-]+(:[1-9][0-9]*)?)*$ ]]; then
    local item
    for item in ${spec//,/ }; do
      if [[ $item == *:* ]]; then echo "${item%%:*} ${item#*:}"; else echo "$item "; fi
    done
  else
    echo "run: $opt '$spec' is neither a hostfile nor a host list h1[:slots],h2[:slots]" >&2
    return 2
  fi
}

hosts_is_local() {
  case $1 in localhost | 127.0.0.1 | "$(hostname)" | "$(hostname -s)") return 0 ;; esac
  return 1
}

# mpm_app is one process, started by an mpirun on this machine: with Open MPI 4.1.4 its
# rank must be on that node too, or connecting the DEM jobs crashes an mpirun.
hosts_check_mpm() {
  local entries
  entries=$(hosts_entries --mpm-hosts "$1") || return 2
  if (($(wc -l <<<"$entries") != 1)); then
    echo "run: --mpm-hosts $1 names $(wc -l <<<"$entries") hosts; mpm_app is one process on one host" >&2
    return 2
  fi
  local host=${entries%% *}
  if ! hosts_is_local "$host"; then
    echo "run: --mpm-hosts $1: mpm_app would run on '$host', but its mpirun runs where scripts/run runs ($(hostname)); with Open MPI 4.1 a job whose ranks are not on its mpirun's node crashes the other job's mpirun when they connect (orte_rml_base_parse_uris, open-mpi/ompi#6818). Run scripts/run on $host (in a batch job: on the first node), or give --mpm-hosts $(hostname)" >&2
    return 2
  fi
}

# One DEM job per host entry. Ranks of a job: its slots; without slots, an even share of
# --dem-ranks, the first jobs getting the remainder, or, without --dem-ranks, DEFAULT per
# host (the backend's default: one per core of this machine for yade and native, as on
# nodes alike). A list with slots on some hosts only is refused, as is a --dem-ranks that
# differs from the sum of the slots.
DEM_JOB_HOSTS=()
DEM_JOB_RANKS=()
dem_jobs_plan() {
  local spec=$1 ranks=$2 default=$3 entries host slots with=0 without=0 sum=0
  entries=$(hosts_entries --dem-hosts "$spec") || return 2
  DEM_JOB_HOSTS=()
  DEM_JOB_RANKS=()
  while read -r host slots; do
    DEM_JOB_HOSTS+=("$host")
    DEM_JOB_RANKS+=("$slots")
    if [[ -n $slots ]]; then with=$((with + 1)); sum=$((sum + slots)); else without=$((without + 1)); fi
  done <<<"$entries"
  local k=${#DEM_JOB_HOSTS[@]} j
  if ((with && without)); then
    echo "run: --dem-hosts $spec: give slots for every host or for none (h1:4,h2:4)" >&2
    return 2
  fi
  if ((with)); then
    if [[ -n $ranks && $ranks -ne $sum ]]; then
      echo "run: --dem-ranks $ranks differs from the $sum slots of --dem-hosts $spec (one DEM job per host, with its slots)" >&2
      return 2
    fi
    return 0
  fi
  if [[ -z $ranks ]]; then
    for ((j = 0; j < k; j++)); do DEM_JOB_RANKS[j]=$default; done
    return 0
  fi
  local total=$ranks
  if ((total < k)); then
    echo "run: $total DEM rank(s) for ${k} DEM hosts: give --dem-ranks >= $k or slots per host (h1:4,h2:4)" >&2
    return 2
  fi
  for ((j = 0; j < k; j++)); do DEM_JOB_RANKS[j]=$((total / k + (j < total % k ? 1 : 0))); done
}
