#!/bin/bash
# agent.sh DIR HOST COMMAND... - Open MPI's remote launcher for the test
# cluster of cluster.sh, in ssh's place (--mca plm_rsh_agent DIR/agent, a
# wrapper that supplies DIR). Like "ssh HOST COMMAND" it runs the command
# string with /bin/sh on HOST, here by entering HOST's network and UTS
# namespaces, with a fresh login-like environment (PATH, HOME) plus the
# host's own variables (cluster.sh setenv) instead of the caller's.
#
# Why this and not an sshd per host: mpirun's side is the same either way
# (its rsh launcher runs "AGENT HOST 'orted ...'" and the orted dials back
# over TCP on the cluster network), while an sshd per host would add host
# keys, a user key, known_hosts, a port and a daemon per host to start, watch
# and kill, and about a second per launch, for nothing the renderer uses.
# What this does not test is ssh itself (authentication, the remote shell's
# start-up files).
dir=$1 host=$2
shift 2
ns=$(cat "$dir/hosts/$host.net" 2>/dev/null)
if [[ -z $ns || ! -e /run/netns/$ns ]]; then
    echo "agent.sh: no host '$host' in the test cluster $dir" >&2
    exit 255  # what ssh returns when it cannot reach the host
fi
mapfile -t vars <"$dir/hosts/$host.env"
[[ -n ${RT_CLUSTER_AGENT_LOG:-} ]] && echo "$host: $*" >>"$RT_CLUSTER_AGENT_LOG"
exec nsenter --net="/run/netns/$ns" --uts="$dir/hosts/$host.uts" -- \
    env -i PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin HOME="${HOME:-/root}" \
    ${RT_CLUSTER_AGENT_LOG:+RT_CLUSTER_AGENT_LOG="$RT_CLUSTER_AGENT_LOG"} "${vars[@]}" /bin/sh -c "$*"
