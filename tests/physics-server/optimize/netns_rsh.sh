#!/usr/bin/env bash
# An rsh agent for OpenMPI (`mpirun --mca plm_rsh_agent netns_rsh.sh`) that
# "logs in" to a host simulated by a Linux network namespace instead of
# using ssh; used by mpi_hosts_test.sh.
#
# OpenMPI runs it as `AGENT [OPTIONS] HOST COMMAND...` (an agent not named
# ssh or rsh gets no options; any leading -x style words are skipped). HOST
# is a name of the hostfile; NETNS_RSH_HOSTS names a file of lines
#
#   HOST NETNS HOSTNAME
#
# and COMMAND (orted's command line, its words quoted for a remote shell, as
# ssh passes them) runs in network namespace NETNS, in a UTS namespace of its
# own whose host name is HOSTNAME (so that the daemon and its ranks report
# HOSTNAME, not this machine's name). Like an ssh client this process stays
# in the caller's namespace until the remote command ends, and exits with its
# status; when that status is not 0 it says so on stderr, naming the host.
# NETNS_RSH_LOG, if set, gets a line per launch: HOST NETNS HOSTNAME COMMAND.
set -u
map=${NETNS_RSH_HOSTS:?netns_rsh: NETNS_RSH_HOSTS is not set}
while [ $# -gt 0 ] && [ "${1#-}" != "$1" ]; do shift; done
host=${1:?netns_rsh: no host}
shift
ns="" hn=""
read -r _ ns hn < <(awk -v h="$host" '$1 == h { print; exit }' "$map")
if [ -z "$ns" ] || [ -z "$hn" ]; then
  echo "netns_rsh: host $host is not in $map" >&2
  exit 255
fi
[ -n "${NETNS_RSH_LOG:-}" ] && echo "$host $ns $hn $*" >>"$NETNS_RSH_LOG"
ip netns exec "$ns" unshare --uts /bin/sh -c "hostname '$hn' && $*"
rc=$?
if [ "$rc" -ne 0 ]; then
  why="exit status $rc"
  [ "$rc" -gt 128 ] && why="$why (killed by signal $((rc - 128)))"
  echo "netns_rsh: $host (network namespace $ns, host name $hn): the remote command ended with $why" >&2
fi
exit "$rc"
