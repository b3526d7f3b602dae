#!/bin/bash
# cluster.sh - a throw-away cluster of N test hosts on this machine (root only).
#
# Host nK is a network namespace plus a UTS namespace (hostname nK) with lo
# up and eth0 = 10.77.25.K/24. eth0 is one end of a veth pair whose other end
# is a port of a bridge that lives in a "switch" network namespace of its own,
# so the machine's own network namespace gets no interface, address or route,
# and nothing but the hosts themselves can be reached from them. The hosts
# share the file system (like a cluster file system) and the mount, PID and
# IPC namespaces.
#
# As a command:
#   eval "$(tests/cluster/cluster.sh up [N])"     # prints: export RT_CLUSTER=DIR
#   tests/cluster/cluster.sh exec n2 hostname      # runs a command on host n2
#   tests/cluster/cluster.sh setenv n2 RT_ACCEL=bvh-scalar   # per-host environment
#   tests/cluster/cluster.sh badlink n3 20 5 1     # delay ms, jitter ms, loss % on n3's link
#   tests/cluster/cluster.sh link n3 down|up       # cut / restore n3's cable
#   tests/cluster/cluster.sh kill n3               # SIGKILL every process on n3
#   tests/cluster/cluster.sh down                  # remove everything (uses $RT_CLUSTER)
# Sourced (tests): cluster_up N; trap cluster_down EXIT; cluster_exec n1 cmd ...
# A sourced cluster_up also starts a watchdog that tears the cluster down if
# the calling shell dies without doing so (e.g. SIGKILL by a ctest timeout).
#
# Open MPI reaches the hosts through its rsh launcher with $RT_CLUSTER/agent
# (see agent.sh for why not an sshd per host):
#   mpirun --mca plm_rsh_agent $RT_CLUSTER/agent --hostfile H ...
#
# Everything made is recorded in $RT_CLUSTER (a mktemp directory) before or as
# it is made, and removed by those names: namespaces rtc-<id>-sw and
# rtc-<id>-nK (<id> = the directory's random suffix, so two clusters or a
# leftover never collide), the UTS namespace files, the processes inside
# the hosts' network namespaces (by PID), the link emulator (by PID).

CLUSTER_HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
CLUSTER_NET=${RT_CLUSTER_NET:-10.77.25}   # the /24 of the hosts (only inside our namespaces)
CLUSTER_WATCHDOG=""

_cluster_log() { printf '[cluster] %s\n' "$*" >&2; }

# cluster_check: can this machine make a cluster? (root, the tools)
cluster_check() {
    local c
    [[ $(id -u) -eq 0 ]] || { echo "not root"; return 1; }
    for c in ip nsenter unshare mount umount; do
        command -v "$c" >/dev/null 2>&1 || { echo "$c missing"; return 1; }
    done
    return 0
}

_cluster_ns() { cat "$RT_CLUSTER/hosts/$1.net" 2>/dev/null; }

cluster_up() {  # [N]
    local n=${1:-3} k h ns sw id why
    why=$(cluster_check) || { _cluster_log "cannot make a cluster: $why"; return 1; }
    RT_CLUSTER=$(mktemp -d /tmp/rt-cluster.XXXXXX) || return 1
    export RT_CLUSTER
    chmod 0755 "$RT_CLUSTER"
    mkdir "$RT_CLUSTER/hosts"
    id=${RT_CLUSTER##*.}
    [[ -n ${CLUSTER_SOURCED:-} ]] && _cluster_watchdog
    sw=rtc-$id-sw
    echo "$sw" >"$RT_CLUSTER/switch"
    ip netns add "$sw" || return 1
    ip -n "$sw" link add br0 type bridge || return 1
    ip -n "$sw" link set br0 up && ip -n "$sw" link set lo up || return 1
    for ((k = 1; k <= n; k++)); do
        h=n$k ns=rtc-$id-$h
        echo "$ns" >"$RT_CLUSTER/hosts/$h.net"
        echo "$CLUSTER_NET.$k" >"$RT_CLUSTER/hosts/$h.addr"
        : >"$RT_CLUSTER/hosts/$h.env"
        ip netns add "$ns" || return 1
        # A UTS namespace kept alive by a bind mount on this file.
        touch "$RT_CLUSTER/hosts/$h.uts"
        unshare --uts="$RT_CLUSTER/hosts/$h.uts" hostname "$h" || return 1
        _cluster_cable "$h" || return 1
        ip -n "$ns" link set lo up || return 1
        echo "$h" >>"$RT_CLUSTER/hostlist"
    done
    # Open MPI's launch agent: one path (plm_rsh_agent splits on blanks).
    printf '#!/bin/sh\nexec %q %q "$@"\n' "$CLUSTER_HERE/agent.sh" "$RT_CLUSTER" >"$RT_CLUSTER/agent"
    chmod 0755 "$RT_CLUSTER/agent"
    _cluster_log "up: $n hosts ($(tr '\n' ' ' <"$RT_CLUSTER/hostlist")) on $CLUSTER_NET.0/24, dir $RT_CLUSTER"
}

# The host's eth0 as a veth pair to a bridge port named after the host.
_cluster_cable() {
    local h=$1 ns sw
    ns=$(_cluster_ns "$h") sw=$(cat "$RT_CLUSTER/switch")
    ip link add eth0 netns "$ns" type veth peer name "$h" netns "$sw" || return 1
    ip -n "$sw" link set "$h" master br0 up || return 1
    _cluster_address "$h"
}
_cluster_address() {
    local h=$1 ns
    ns=$(_cluster_ns "$h")
    ip -n "$ns" addr add "$(cat "$RT_CLUSTER/hosts/$h.addr")/24" dev eth0 || return 1
    ip -n "$ns" link set eth0 up
}

# cluster_exec HOST CMD...: CMD on HOST, with the caller's environment plus
# the host's own (cluster_setenv), like a user logged in on that node.
cluster_exec() {
    local h=$1 ns vars=()
    shift
    ns=$(_cluster_ns "$h")
    [[ -n $ns ]] || { _cluster_log "no host '$h' in ${RT_CLUSTER:-<no cluster>}"; return 255; }
    mapfile -t vars <"$RT_CLUSTER/hosts/$h.env"
    nsenter --net="/run/netns/$ns" --uts="$RT_CLUSTER/hosts/$h.uts" -- env "${vars[@]}" "$@"
}

# cluster_setenv HOST VAR=VALUE...: environment of every process started on
# HOST from now on (cluster_exec and the launch agent), as a site sets a
# node's defaults in its login environment.
cluster_setenv() {
    local h=$1
    shift
    [[ -n $(_cluster_ns "$h") ]] || { _cluster_log "no host '$h'"; return 1; }
    printf '%s\n' "$@" >>"$RT_CLUSTER/hosts/$h.env"
}
cluster_clearenv() { : >"$RT_CLUSTER/hosts/$1.env"; }

# cluster_link HOST down|up: pull or plug HOST's cable (its switch port).
cluster_link() {
    ip -n "$(cat "$RT_CLUSTER/switch")" link set "$1" "$2"
}

# cluster_kill HOST [SIGNAL]: signal every process in HOST's network
# namespace (by PID), as if the node lost power.
cluster_kill() {
    local pids
    pids=$(ip netns pids "$(_cluster_ns "$1")" 2>/dev/null)
    # shellcheck disable=SC2086
    [[ -n $pids ]] && kill -"${2:-KILL}" $pids 2>/dev/null
    return 0
}

# cluster_badlink HOST DELAY_MS JITTER_MS LOSS_PCT: a bad cable for HOST.
# With the kernel's netem qdisc: netem on HOST's eth0 (its outgoing frames).
# Kernels without netem (CONFIG_NET_SCH_NETEM unset, like this project's CI
# machine) get the same from badlink.py: HOST's veth is replaced by two tap
# devices and a process that relays frames between them, each one delayed by
# DELAY +- JITTER ms and dropped with LOSS %, in both directions.
# Prints which of the two it used.
cluster_badlink() {
    local h=$1 delay=$2 jitter=$3 loss=$4 ns sw pid i
    ns=$(_cluster_ns "$h") sw=$(cat "$RT_CLUSTER/switch")
    if [[ ${RT_CLUSTER_NO_NETEM:-0} != 1 ]] &&
        tc -n "$ns" qdisc add dev eth0 root netem delay "${delay}ms" "${jitter}ms" loss "${loss}%" 2>/dev/null; then
        echo "netem"
        return 0
    fi
    ip -n "$ns" link del eth0 || return 1   # takes its peer (the switch port) with it
    ip netns exec "$sw" /usr/bin/python3 "$CLUSTER_HERE/badlink.py" "t$h" "x$h" "$delay" "$jitter" "$loss" \
        >"$RT_CLUSTER/badlink-$h.log" 2>&1 </dev/null &
    pid=$!
    echo "$pid" >"$RT_CLUSTER/badlink-$h.pid"
    for ((i = 0; i < 50; i++)); do
        grep -q '^ready' "$RT_CLUSTER/badlink-$h.log" 2>/dev/null && break
        kill -0 "$pid" 2>/dev/null || break
        sleep 0.1
    done
    grep -q '^ready' "$RT_CLUSTER/badlink-$h.log" ||
        { _cluster_log "badlink.py did not start: $(cat "$RT_CLUSTER/badlink-$h.log")"; return 1; }
    ip -n "$sw" link set "x$h" netns "$ns" || return 1
    ip -n "$ns" link set "x$h" name eth0 || return 1
    ip -n "$sw" link set "t$h" master br0 up || return 1
    _cluster_address "$h" || return 1
    echo "badlink.py"
}

# cluster_down [DIR]: stop every process in the hosts and the switch (TERM,
# then KILL, by PID), delete the namespaces by name, unmount the UTS files,
# remove the directory. Idempotent; safe at any stage of cluster_up.
cluster_down() {
    local rc=$? dir=${1:-${RT_CLUSTER:-}} f ns all=() pids i
    if [[ -n $CLUSTER_WATCHDOG ]]; then
        kill "$CLUSTER_WATCHDOG" 2>/dev/null
        wait "$CLUSTER_WATCHDOG" 2>/dev/null
        CLUSTER_WATCHDOG=""
    fi
    [[ -n $dir && -d $dir && $dir == /tmp/rt-cluster.* ]] || return "$rc"
    for f in "$dir"/hosts/*.net "$dir"/switch; do
        [[ -f $f ]] && all+=("$(cat "$f")")
    done
    for i in 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20; do
        pids=""
        for ns in "${all[@]}"; do
            [[ -e /run/netns/$ns ]] && pids+=" $(ip netns pids "$ns" 2>/dev/null | tr '\n' ' ')"
        done
        [[ -z ${pids// /} ]] && break
        # shellcheck disable=SC2086
        if ((i == 0)); then kill -TERM $pids 2>/dev/null; elif ((i >= 10)); then kill -KILL $pids 2>/dev/null; fi
        sleep 0.2
    done
    for ns in "${all[@]}"; do
        [[ -e /run/netns/$ns ]] && ip netns del "$ns"
    done
    for f in "$dir"/hosts/*.uts; do
        [[ -f $f ]] && umount "$f" 2>/dev/null
    done
    if [[ ${RT_CLUSTER_KEEP:-0} == 1 ]]; then
        _cluster_log "kept $dir"
    else
        rm -rf "$dir"
    fi
    [[ $dir == "${RT_CLUSTER:-}" ]] && unset RT_CLUSTER
    return "$rc"
}

# If the shell that made the cluster dies without cluster_down, tear it down.
_cluster_watchdog() {
    local parent=$$ dir=$RT_CLUSTER
    (
        trap - EXIT
        trap 'exit 0' TERM
        while kill -0 "$parent" 2>/dev/null && [[ -d $dir ]]; do sleep 1; done
        [[ -d $dir ]] && CLUSTER_WATCHDOG="" cluster_down "$dir"
    ) >/dev/null 2>&1 </dev/null &
    CLUSTER_WATCHDOG=$!
}

if [[ ${BASH_SOURCE[0]} == "$0" ]]; then
    set -u
    cmd=${1:-}
    shift || true
    case $cmd in
        up)
            cluster_up "${1:-3}" >&2 || { cluster_down; exit 1; }
            echo "export RT_CLUSTER=$RT_CLUSTER" ;;
        down) cluster_down "${1:-${RT_CLUSTER:-}}" ;;
        exec | setenv | link | kill | badlink)
            [[ -n ${RT_CLUSTER:-} ]] || { _cluster_log "RT_CLUSTER is not set (eval \"\$($0 up)\")"; exit 2; }
            "cluster_$cmd" "$@" ;;
        *)
            echo "usage: $0 up [N] | down [DIR] | exec HOST CMD... | setenv HOST VAR=VALUE... |" >&2
            echo "       link HOST up|down | kill HOST [SIG] | badlink HOST DELAY_MS JITTER_MS LOSS_PCT" >&2
            exit 2 ;;
    esac
else
    CLUSTER_SOURCED=1
fi
