# shellcheck shell=bash
# slurm_env.sh - throw-away single-node Slurm cluster for tests (sourced).
#
# Usage:
#   source tests/slurm/slurm_env.sh
#   trap slurm_down EXIT
#   slurm_install          # apt-get slurm-wlm + munge if missing (root only)
#   slurm_up               # private munged + slurmctld + slurmd, exports SLURM_CONF
#   sbatch ...             # talks to the private cluster only
#   slurm_down             # idempotent; safe after a half-failed slurm_up
#
# Everything lives in one mktemp directory ($SLURM_ENV_DIR): slurm.conf, state,
# spool, logs, munge key, munge socket.  Nothing under /etc, /run or /var is
# touched, and a system munged/slurm (if any) is left alone: the private
# daemons use their own munge socket (AuthInfo=socket=...) and free TCP ports.
#
# Tunables (environment, read by slurm_up):
#   SLURM_ENV_UP_TIMEOUT   seconds to wait for the node to become idle (60)
#   SLURM_ENV_KILLWAIT     KillWait: seconds between SIGTERM and SIGKILL (10)
#   SLURM_ENV_CRED_EXPIRE  cred_expire; also the delay before a requeued job
#                          may start again (Slurm default 120; here 5)
#   SLURM_ENV_PARTITION    partition name (rtmpi)
#   SLURM_ENV_KEEP         if 1, slurm_down keeps the directory (debugging)
#
# After slurm_up: SLURM_CONF, SLURM_ENV_DIR, SLURM_ENV_NODE, SLURM_ENV_CPUS,
# SLURM_ENV_PARTITION, SLURM_ENV_MPI (pmix or none) are set.

SLURM_ENV_DIR="${SLURM_ENV_DIR:-}"
SLURM_ENV_PIDS=()      # "pid:name" of every daemon slurm_up started
SLURM_ENV_NODE=""
SLURM_ENV_CPUS=""
SLURM_ENV_MPI=""
SLURM_ENV_CLUSTER=rtmpi-test
SLURM_ENV_WATCHDOG=""  # pid of the reaper that cleans up if our shell is SIGKILLed

# The scheduling, plugin and timeout settings every private test cluster
# uses (this one and tests/cluster/slurm_cluster.sh), as slurm.conf lines on
# stdout: slurm_conf_policy MPI_PLUGIN KILLWAIT_SECONDS
slurm_conf_policy() {
    cat <<EOF
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
# fast scheduling so tests do not sit in PENDING (defaults: 60 s / 30 s)
SchedulerParameters=sched_interval=2,bf_interval=1
MpiDefault=$1
ReturnToService=2
JobRequeue=1
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
# generous timeouts: a loaded 2-core CI box must not mark a node down
SlurmctldTimeout=300
SlurmdTimeout=300
MessageTimeout=60
BatchStartTimeout=60
TCPTimeout=10
InactiveLimit=0
Waittime=0
# keep finished jobs visible to 'scontrol show job' for 10 minutes
MinJobAge=600
KillWait=$2
OverTimeLimit=0
EOF
}

_slurm_log() { printf '[slurm_env] %s\n' "$*" >&2; }

# slurm_install: install slurm-wlm + munge (and openmpi-bin) when missing.
slurm_install() {
    if [[ $(id -u) -ne 0 ]] && ! command -v sudo >/dev/null 2>&1; then
        command -v slurmctld >/dev/null 2>&1 || PATH="$PATH:/usr/sbin:/sbin" command -v slurmctld >/dev/null 2>&1 ||
            { _slurm_log "FAIL: Slurm missing and cannot install (not root)"; return 1; }
        return 0
    fi
    "$(dirname "${BASH_SOURCE[0]}")/../../scripts/install_packages.sh" slurm-wlm munge openmpi-bin >/dev/null ||
        { _slurm_log "FAIL: installing slurm-wlm munge openmpi-bin"; return 1; }
}

# Is TCP port $1 on localhost free? (something answers -> in use)
_slurm_port_free() {
    ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null
}

# Start "$@" in the background with output to log $1, record pid.
_slurm_spawn() {
    local name=$1 log=$2; shift 2
    # Marker variable: slurm_down and the watchdog find our daemons (and any
    # child inheriting their environment) by it.
    SLURM_ENV_TAG="$SLURM_ENV_DIR" "$@" >"$log" 2>&1 </dev/null &
    SLURM_ENV_PIDS+=("$!:$name")
}

_slurm_alive() {  # pid:name still running?
    local pid=${1%%:*}
    kill -0 "$pid" 2>/dev/null && [[ ! -r /proc/$pid/stat || $(awk '{print $3}' "/proc/$pid/stat" 2>/dev/null) != Z ]]
}

_slurm_dump_logs() {
    local f
    for f in "$SLURM_ENV_DIR"/log/*.log; do
        [[ -f $f ]] || continue
        _slurm_log "---- tail $f"
        tail -n 15 "$f" >&2
    done
}

slurm_up() {
    local sbin
    for sbin in /usr/sbin /sbin; do [[ :$PATH: == *":$sbin:"* ]] || PATH="$PATH:$sbin"; done
    local c
    for c in slurmctld slurmd munged sinfo; do
        command -v "$c" >/dev/null 2>&1 || { _slurm_log "FAIL: $c not found (run slurm_install)"; return 1; }
    done

    SLURM_ENV_DIR=$(mktemp -d "${TMPDIR:-/tmp}/rt-slurm.XXXXXX") || { _slurm_log "FAIL: mktemp"; return 1; }
    # munged insists that every directory on the socket path is searchable
    # by all (o+x) and not writable by others.
    chmod 0711 "$SLURM_ENV_DIR"
    local d=$SLURM_ENV_DIR
    mkdir -p "$d"/{state,spool,log,run,munge} && chmod 0755 "$d/munge" || return 1
    local t0=$SECONDS
    _slurm_start_watchdog

    # --- node facts from slurmd -C (NodeName=vm CPUs=2 Boards=1 ... RealMemory=N)
    local hw
    hw=$(slurmd -C 2>/dev/null | head -n 1)
    [[ $hw == NodeName=* ]] || { _slurm_log "FAIL: 'slurmd -C' gave: $hw"; return 1; }
    SLURM_ENV_NODE=$(sed -n 's/.*NodeName=\([^ ]*\).*/\1/p' <<<"$hw")
    SLURM_ENV_CPUS=$(sed -n 's/.*CPUs=\([0-9]*\).*/\1/p' <<<"$hw")
    local hwspec=${hw#NodeName=* }   # "CPUs=.. Boards=.. ... RealMemory=.."
    SLURM_ENV_PARTITION=${SLURM_ENV_PARTITION:-rtmpi}

    # --- MPI plugin: pmix if Slurm has the plugin, else none
    SLURM_ENV_MPI=none
    if compgen -G "/usr/lib/*/slurm-wlm/mpi_pmix*.so" >/dev/null ||
       compgen -G "/usr/lib*/slurm/mpi_pmix*.so" >/dev/null; then
        SLURM_ENV_MPI=pmix
    fi

    # --- two free consecutive ports (avoid a system slurm on 6817/6818)
    local port="" p i
    for i in $(seq 1 50); do
        p=$(( 20000 + (RANDOM % 20000) ))
        if _slurm_port_free "$p" && _slurm_port_free $((p + 1)); then port=$p; break; fi
    done
    [[ -n $port ]] || { _slurm_log "FAIL: no free TCP port pair"; return 1; }

    # --- munge: private key + socket
    local sock=$d/munge/munge.socket.2
    if command -v mungekey >/dev/null 2>&1; then
        mungekey -c -k "$d/munge/munge.key" >/dev/null 2>&1 || return 1
    else
        dd if=/dev/urandom of="$d/munge/munge.key" bs=1024 count=1 status=none || return 1
    fi
    chmod 0400 "$d/munge/munge.key"
    _slurm_spawn munged "$d/log/munged.out" munged -F -S "$sock" \
        --key-file="$d/munge/munge.key" --log-file="$d/log/munged.log" \
        --pid-file="$d/munge/munged.pid" --seed-file="$d/munge/munged.seed"
    for i in $(seq 1 50); do
        [[ -S $sock ]] && break
        _slurm_alive "${SLURM_ENV_PIDS[-1]}" || break
        sleep 0.1
    done
    if ! munge -S "$sock" -n 2>/dev/null | unmunge -S "$sock" >/dev/null 2>&1; then
        _slurm_log "FAIL: private munged did not come up (socket $sock)"
        cat "$d/log/munged.out" >&2 2>/dev/null; _slurm_dump_logs
        return 1
    fi

    # --- slurm.conf
    export SLURM_CONF=$d/slurm.conf
    cat >"$SLURM_CONF" <<EOF
# generated by tests/slurm/slurm_env.sh - private test cluster
ClusterName=$SLURM_ENV_CLUSTER
SlurmctldHost=localhost
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sock,cred_expire=${SLURM_ENV_CRED_EXPIRE:-5}
StateSaveLocation=$d/state
SlurmdSpoolDir=$d/spool
SlurmctldPidFile=$d/run/slurmctld.pid
SlurmdPidFile=$d/run/slurmd.pid
SlurmctldLogFile=$d/log/slurmctld.log
SlurmdLogFile=$d/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
$(slurm_conf_policy "$SLURM_ENV_MPI" "${SLURM_ENV_KILLWAIT:-10}")
NodeName=$SLURM_ENV_NODE NodeAddr=127.0.0.1 $hwspec State=UNKNOWN
PartitionName=$SLURM_ENV_PARTITION Nodes=$SLURM_ENV_NODE Default=YES MaxTime=INFINITE State=UP
EOF

    # --- daemons (foreground mode, backgrounded here so we own the PIDs)
    _slurm_spawn slurmctld "$d/log/slurmctld.out" slurmctld -D -f "$SLURM_CONF"
    _slurm_spawn slurmd "$d/log/slurmd.out" slurmd -D -f "$SLURM_CONF" -N "$SLURM_ENV_NODE"

    # --- wait for idle node (bounded)
    local limit=${SLURM_ENV_UP_TIMEOUT:-60} state="" e
    while :; do
        state=$(timeout 10 sinfo -h -N -n "$SLURM_ENV_NODE" -o '%t' 2>/dev/null | head -n 1)
        [[ $state == idle ]] && break
        for e in "${SLURM_ENV_PIDS[@]}"; do
            if ! _slurm_alive "$e"; then
                _slurm_log "FAIL: daemon ${e#*:} (pid ${e%%:*}) exited during start-up"
                cat "$d/log/${e#*:}.out" >&2 2>/dev/null; _slurm_dump_logs
                return 1
            fi
        done
        if (( SECONDS - t0 >= limit )); then
            _slurm_log "FAIL: node $SLURM_ENV_NODE not idle after ${limit}s (state '${state:-no answer}')"
            _slurm_dump_logs
            return 1
        fi
        sleep 0.5
    done
    export SLURM_ENV_DIR SLURM_ENV_NODE SLURM_ENV_CPUS SLURM_ENV_PARTITION SLURM_ENV_MPI
    _slurm_log "up in $((SECONDS - t0))s: node $SLURM_ENV_NODE ($SLURM_ENV_CPUS cpus) idle, ports $port/$((port + 1)), mpi=$SLURM_ENV_MPI, dir $d"
}

# PIDs left over from our cluster: processes carrying our marker variable
# (daemons), slurmstepd processes holding files of our directory open, and
# job processes (SLURM_CONF and SLURM_CLUSTER_NAME are ours).
# shellcheck disable=SC2013  # /proc paths contain no blanks
_slurm_env_strays() {
    local dir=${1:-$SLURM_ENV_DIR} f p
    [[ -n $dir ]] || return 0
    {
        # daemons started by _slurm_spawn
        grep -lzxF "SLURM_ENV_TAG=$dir" /proc/[0-9]*/environ 2>/dev/null
        # job processes of our cluster
        for f in $(grep -lzxF "SLURM_CONF=$dir/slurm.conf" /proc/[0-9]*/environ 2>/dev/null); do
            grep -qzxF "SLURM_CLUSTER_NAME=$SLURM_ENV_CLUSTER" "$f" 2>/dev/null && echo "$f"
        done
        # slurmstepd starts with an empty environment; it keeps our
        # slurmd.log open, which identifies it.
        for f in $(grep -lx slurmstepd /proc/[0-9]*/comm 2>/dev/null); do
            for p in "${f%/comm}"/fd/*; do
                if [[ $(readlink "$p" 2>/dev/null) == "$dir"/* ]]; then echo "$f"; break; fi
            done
        done
    } | sed -n 's|^/proc/\([0-9]*\)/.*|\1|p' | sort -u | grep -vxF -e "$$" -e "${BASHPID:-$$}"
    return 0
}

# Reaper: if the shell that sourced us dies without running slurm_down (e.g.
# SIGKILL from a test harness timeout), kill everything carrying our marker
# and remove the directory.  slurm_down stops it first.
_slurm_start_watchdog() {
    local parent=$$ dir=$SLURM_ENV_DIR
    (
        trap - EXIT
        trap 'exit 0' TERM
        while kill -0 "$parent" 2>/dev/null && [[ -d $dir ]]; do sleep 1; done
        [[ -d $dir ]] || exit 0
        strays=$(_slurm_env_strays "$dir")
        # shellcheck disable=SC2086
        [[ -n $strays ]] && kill -TERM $strays 2>/dev/null && sleep 3
        strays=$(_slurm_env_strays "$dir")
        # shellcheck disable=SC2086
        [[ -n $strays ]] && kill -KILL $strays 2>/dev/null
        rm -rf "$dir"
    ) >/dev/null 2>&1 </dev/null &
    SLURM_ENV_WATCHDOG=$!
}

# slurm_down: cancel jobs, stop our daemons (TERM, then KILL), remove the dir.
# Idempotent and safe from 'trap slurm_down EXIT' at any stage of slurm_up.
slurm_down() {
    local rc=$? opts=$-
    set +e
    local e i
    if [[ -n $SLURM_ENV_WATCHDOG ]]; then
        kill -TERM "$SLURM_ENV_WATCHDOG" 2>/dev/null
        wait "$SLURM_ENV_WATCHDOG" 2>/dev/null
        SLURM_ENV_WATCHDOG=""
    fi
    if [[ -n $SLURM_ENV_DIR && -f $SLURM_ENV_DIR/slurm.conf ]]; then
        # Cancel all jobs so slurmstepd/job processes end cleanly (bounded).
        if timeout 10 scancel --full -p "${SLURM_ENV_PARTITION:-rtmpi}" >/dev/null 2>&1; then
            for i in $(seq 1 20); do
                [[ -z $(timeout 5 squeue -h -t R,CG -o %i 2>/dev/null) ]] && break
                sleep 0.5
            done
        fi
    fi
    # Reverse start order: slurmd, slurmctld, munged.
    for (( i = ${#SLURM_ENV_PIDS[@]} - 1; i >= 0; i-- )); do
        e=${SLURM_ENV_PIDS[i]}
        _slurm_alive "$e" && kill -TERM "${e%%:*}" 2>/dev/null
    done
    for i in $(seq 1 50); do      # up to 5 s
        local any=0
        for e in "${SLURM_ENV_PIDS[@]}"; do _slurm_alive "$e" && any=1; done
        (( any )) || break
        sleep 0.1
    done
    for e in "${SLURM_ENV_PIDS[@]}"; do
        if _slurm_alive "$e"; then
            _slurm_log "killing ${e#*:} (pid ${e%%:*}) with SIGKILL"
            kill -KILL "${e%%:*}" 2>/dev/null
        fi
        wait "${e%%:*}" 2>/dev/null
    done
    SLURM_ENV_PIDS=()
    # Leftover slurmstepd / job processes of this cluster (by marker, by PID).
    local strays
    strays=$(_slurm_env_strays)
    if [[ -n $strays ]]; then
        # shellcheck disable=SC2086
        kill -TERM $strays 2>/dev/null; sleep 1
        strays=$(_slurm_env_strays)
        # shellcheck disable=SC2086
        [[ -n $strays ]] && kill -KILL $strays 2>/dev/null
    fi
    if [[ -n $SLURM_ENV_DIR && -d $SLURM_ENV_DIR ]]; then
        if [[ ${SLURM_ENV_KEEP:-0} == 1 ]]; then
            _slurm_log "kept $SLURM_ENV_DIR"
        else
            rm -rf "$SLURM_ENV_DIR"
        fi
    fi
    if [[ -n ${SLURM_CONF:-} && $SLURM_CONF == "${SLURM_ENV_DIR:-/nonexistent}"/* ]]; then
        unset SLURM_CONF
    fi
    SLURM_ENV_DIR=""
    [[ $opts == *e* ]] && set -e
    return "$rc"
}
