#!/bin/sh
# Open MPI rsh agent for hosts that are Linux network namespaces on this machine (the
# multihost test, docs/cluster.md): mpirun calls `AGENT HOST COMMAND...` as it would call
# ssh; this runs COMMAND in the network namespace named HOST, in its own UTS namespace whose
# host name is HOST (so Open MPI and mpm_app see one host per namespace). Needs root.
# Use: MPMDEM_RSH_AGENT=/path/to/netns_agent.sh scripts/run ... --dem-hosts HOST1,HOST2
set -eu
host=${1:?usage: netns_agent.sh HOST COMMAND...}
shift
case $host in *[!A-Za-z0-9._-]*) echo "netns_agent: bad host name '$host'" >&2; exit 2 ;; esac
# Like ssh, the remote command is one shell command line made of the remaining words.
exec ip netns exec "$host" unshare --uts sh -c "hostname '$host' && $*"
