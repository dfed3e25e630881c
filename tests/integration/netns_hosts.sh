# shellcheck shell=bash
# Hosts made of Linux network namespaces for the multi-node tests (docs/cluster.md, "Worked
# example"): each host a namespace with one veth link to a bridge in a switch namespace and
# its own address in a private /24; processes started in it get its name as host name. Source
# it after common.sh, then:
#   netns_skip_unless_root                      exits 77 (CTest: skipped) without the privilege
#   netns_make TAG NAME...                      hosts mpmdem-TAG-<name> (HOST[name]), net $NET
#   on_host HOST CMD...                         CMD in HOST's namespace, as a login there
#   netns_cut HOST                              cut HOST's link at the switch
#   netns_no_process_left WHEN                  ok/fail: nothing runs in any namespace
# The namespaces are removed at the exit (trap), also on failure, after the processes left in
# them are killed by PID (ip netns pids); those of an earlier run whose shell is gone too.
# Needs: ok, fail (the test's), and `run_pid` (a scripts/run in the background, or empty).

skip() {
  echo "SKIPPED: $*"
  exit 77
}

netns_skip_unless_root() {
  [[ $(id -u) -eq 0 ]] || skip "network namespaces need root (uid $(id -u))"
  command -v ip >/dev/null || skip "no 'ip' command (Debian package iproute2)"
  command -v unshare >/dev/null || skip "no 'unshare' command (Debian package util-linux)"
}

NETNS_MADE=()
declare -A HOST PORT ADDR
NET=""
SWITCH=""
run_pid=""

netns_cleanup() {
  if [[ -n $run_pid ]] && kill -0 "$run_pid" 2>/dev/null; then
    kill -TERM "$run_pid" 2>/dev/null
    for _ in $(seq 1 100); do kill -0 "$run_pid" 2>/dev/null || break; sleep 0.1; done
  fi
  local ns pid
  for ns in "${NETNS_MADE[@]}"; do
    for pid in $(ip netns pids "$ns" 2>/dev/null); do kill -KILL "$pid" 2>/dev/null; done
  done
  for ns in "${NETNS_MADE[@]}"; do ip netns delete "$ns" 2>/dev/null; done
}

# netns_make TAG NAME...: the switch and one host per NAME (a, b, ...).
netns_make() {
  local tag=$1 ns owner
  shift
  # Namespaces of an earlier run of these tests whose shell is gone (killed by a CTest
  # timeout, so its trap never ran): stop what runs in them (by PID) and delete them.
  for ns in $(ip netns list 2>/dev/null | grep -oE '^mpmdem-(mh|mn)[0-9]+-[a-z]+\b'); do
    owner=${ns#mpmdem-m?}
    owner=${owner%%-*}
    kill -0 "$owner" 2>/dev/null && continue
    for pid in $(ip netns pids "$ns" 2>/dev/null); do kill -KILL "$pid" 2>/dev/null; done
    ip netns delete "$ns" 2>/dev/null && echo "removed the stale namespace $ns (its test, pid $owner, is gone)"
  done
  trap netns_cleanup EXIT
  local i
  for i in $(seq $(($$ % 200 + 1)) 254) $(seq 1 254); do
    ip -o -4 addr show | grep -q " 10\.213\.$i\." || { NET=10.213.$i; break; }
  done
  [[ -n $NET ]] || skip "no free /24 in 10.213.0.0/16"
  SWITCH=mpmdem-$tag-sw
  local err
  if ! err=$(ip netns add "$SWITCH" 2>&1); then skip "cannot create a network namespace: $err"; fi
  NETNS_MADE+=("$SWITCH")
  unshare --uts true 2>/dev/null || skip "cannot create a UTS namespace (unshare --uts)"
  ip -n "$SWITCH" link add br0 type bridge && ip -n "$SWITCH" link set br0 up || return 1
  local n=1 name h
  for name in "$@"; do
    h=mpmdem-$tag-$name
    HOST[$name]=$h
    ip netns add "$h" || return 1
    NETNS_MADE+=("$h")
    PORT[$name]=port$n
    ADDR[$name]=$NET.$n
    ip -n "$h" link set lo up &&
      ip link add eth0 netns "$h" type veth peer name "port$n" netns "$SWITCH" &&
      ip -n "$h" addr add "$NET.$n/24" dev eth0 && ip -n "$h" link set eth0 up &&
      ip -n "$SWITCH" link set "port$n" master br0 && ip -n "$SWITCH" link set "port$n" up || return 1
    n=$((n + 1))
  done
}

on_host() {
  local h=$1
  shift
  ip netns exec "$h" unshare --uts sh -c 'hostname "$0" && exec "$@"' "$h" "$@"
}

# netns_cut NAME: the host's port on the switch goes down (its link is cut).
netns_cut() {
  ip -n "$SWITCH" link set "${PORT[$1]}" down
}

netns_no_process_left() {
  local ns left=""
  for ns in "${NETNS_MADE[@]}"; do
    [[ -z $(ip netns pids "$ns") ]] || left+=" $ns:$(ip netns pids "$ns" | tr '\n' ' ')"
  done
  if [[ -z $left ]]; then ok "no process left on any host $1"; else fail "processes left $1:$left"; fi
}
