#!/bin/bash
# test_cluster.sh CASE BIN SERIAL - ctest driver (label: cluster): rt-mpi on
# a test cluster of 3 hosts (cluster.sh: network + UTS namespaces on a
# bridge), launched by mpirun through its rsh launcher, TCP between hosts.
# Every image must be byte-identical to SERIAL's (the one-process build).
#   hostfile  3 x 1 rank x 2 threads, 3 x 2 ranks x 1 thread, uneven slots
#   mixed     one host on the SSE2 box test, one on the portable scalar one,
#             one on the default, each with its own thread count (RT_ACCEL
#             and OMP_NUM_THREADS in the host's environment); frame jobs
#             there against the one-process build's --frame N
#   badnet    one host's link with 20 ms +- 5 ms delay and 1 % loss
#   losthost  every process on one host killed mid-render: the job ends
#             within seconds; exit 0 with the image, or a checkpoint from
#             which --resume (on the hosts left) gives the image
#   lostsurvive  every rank on one host killed mid-render under mpirun
#             --enable-recovery (--lease 2): the survivors finish by
#             themselves, exit 0, the same bytes
#   slurmlost every process of one host (slurmd too) killed mid-render of an
#             sbatch job launched with srun: the script exits 0 with the
#             image of an uninterrupted run
#   slurm     slurmctld + a slurmd per host: scripts/slurm/rt-mpi.sbatch with
#             sbatch -N 3 (srun --mpi=pmix, and mpirun in the allocation); a
#             job signalled as before its time limit requeues itself and
#             resumes on the nodes it then gets
# Exit 0 all passed, 1 a check failed, 77 cannot run here (not root, no tools;
# a failure instead when RT_REQUIRE_ALL=1, as in scripts/test.sh).
CASE=${1:-} BIN=${2:-} SERIAL=${3:-}
if [[ -z $CASE || ! -x $BIN || ! -x $SERIAL ]]; then
    echo "usage: $0 hostfile|mixed|badnet|losthost|lostsurvive|slurm|slurmlost RT_MPI_BINARY RT_MPI_SERIAL_BINARY" >&2
    exit 2
fi
BIN=$(readlink -f "$BIN") SERIAL=$(readlink -f "$SERIAL")
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
source "$HERE/../support/lib.sh"
source "$HERE/cluster.sh"
trap 'cluster_down; rm -rf "$WORK"' EXIT
T0=$(date +%s.%N)
note() { printf -- '---- [%5.1fs] %s\n' "$(secs "$T0" "$(now)")" "$*"; }
now() { date +%s.%N; }
secs() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.2f", b - a}'; } # from to

if ! why=$(cluster_check) || ! command -v mpirun >/dev/null 2>&1 ||
    { [[ $CASE == slurm* ]] && ! PATH=$PATH:/usr/sbin command -v slurmctld >/dev/null 2>&1; }; then
    [[ -z $why ]] && ! command -v mpirun >/dev/null 2>&1 && why="mpirun missing"
    why=${why:-"Slurm (slurm-wlm) not installed"}
    [[ ${RT_REQUIRE_ALL:-0} == 1 ]] && { echo "FAIL: cannot run here: $why"; exit 1; }
    echo "SKIP: $why"
    exit 77
fi
cluster_up 3 || { echo "FAIL: cluster_up"; exit 1; }
NET=$(cut -d. -f1-3 <"$RT_CLUSTER/hosts/n1.addr").0/24

# mpirun on n1 (the first node, as a user would on a real cluster), reaching
# the others through the launch agent; TCP only on the cluster network, and
# oob (mpirun <-> orted) on it too.
cmpirun() { # seconds hostfile mpirun-args...
    local secs=$1 hf=$2
    shift 2
    timeout -k 5 "$secs" "$HERE/cluster.sh" exec n1 mpirun --hostfile "$hf" --mca plm_rsh_agent "$RT_CLUSTER/agent" \
        --mca btl self,vader,tcp --mca btl_tcp_if_include "$NET" --mca oob_tcp_if_include "$NET" \
        --bind-to none "$@"
}
hostfile() { # name "n1 slots=1" ... -> path
    printf '%s\n' "${@:2}" >"$WORK/$1.hosts"
    echo "$WORK/$1.hosts"
}
# How many ranks of a job on this hostfile each host gets: "n1:1 n2:3 n3:2".
placement() { # hostfile np
    cmpirun 60 "$1" -np "$2" hostname | sort | uniq -c | awk '{printf "%s%s:%s", (NR > 1 ? " " : ""), $2, $1}'
}
# Bytes that crossed HOST's eth0 in both directions so far.
eth_bytes() {
    # (/proc/net/dev: /sys/class/net shows the namespace that mounted /sys)
    cluster_exec "$1" cat /proc/net/dev | awk '$1 == "eth0:" {print $2 + $10}'
}
# Same image as the one-process reference, else the first differing byte.
same_image() { # label file
    if [[ -s $REF ]] && cmp -s "$REF" "$2"; then
        pass "$1: image identical to the one-process render ($(stat -c %s "$2") bytes)"
    else
        fail "$1: image differs from the one-process render: $(cmp "$REF" "$2" 2>&1)"
    fi
}
show() { [[ -f $1 ]] && sed 's/^/     | /' "$1" | tail -n "${2:-25}"; return 0; } # file [lines]

IMG=(--width 160 --height 100 -s 4 --no-checkpoint -q)
REF=$WORK/ref.png
"$SERIAL" "${IMG[@]}" -j 2 -o "$REF" >"$WORK/ref.out" || fail "one-process reference render: $(cat "$WORK/ref.out")"
note "reference: $SERIAL $(grep 'image hash' "$WORK/ref.out")"

case $CASE in
hostfile)
    # name | hostfile lines | -np | -j | expected placement
    run_hostfile() {
        local name=$1 np=$2 j=$3 want=$4 hf got t b0 b1
        shift 4
        hf=$(hostfile "$name" "$@")
        got=$(placement "$hf" "$np")
        check_eq "$name: ranks per host" "$got" "$want"
        b0=$(eth_bytes n3)
        t=$(now)
        cmpirun 120 "$hf" -np "$np" "$BIN" "${IMG[@]}" -j "$j" -o "$WORK/$name.png" --stats "$WORK/$name.json" \
            >"$WORK/$name.out" 2>&1
        check_eq "$name: exit status" $? 0
        # --stats names each rank's host: the same placement
        check_eq "$name: hosts in --stats" "$(python3 -c 'import collections, json, sys
c = collections.Counter(r["host"] for r in json.load(open(sys.argv[1]))["per_rank"])
print(" ".join("%s:%d" % kv for kv in sorted(c.items())))' "$WORK/$name.json")" "$want"
        b1=$(eth_bytes n3)
        note "$name: $(secs "$t" "$(now)") s; $((b1 - b0)) bytes through n3's eth0"
        same_image "$name ($np ranks, -j $j)" "$WORK/$name.png" || show "$WORK/$name.out"
        # The ranks on n3 sent their rows to rank 0 on n1 through n3's
        # cable: at least a sixth of the 160x100 image's 24-byte sums.
        (( b1 - b0 > 160 * 100 * 24 / 6 )) && pass "$name: $((b1 - b0)) bytes crossed n3's eth0 (TCP between hosts)" ||
            fail "$name: only $((b1 - b0)) bytes crossed n3's eth0: the ranks there did not talk over the network"
    }
    run_hostfile 3x1x2 3 2 "n1:1 n2:1 n3:1" "n1 slots=1" "n2 slots=1" "n3 slots=1"
    run_hostfile 3x2x1 6 1 "n1:2 n2:2 n3:2" "n1 slots=2" "n2 slots=2" "n3 slots=2"
    run_hostfile uneven 6 1 "n1:1 n2:3 n3:2" "n1 slots=1" "n2 slots=3" "n3 slots=2"
    # Where each host's orted came from: mpirun on n1 started n2 and n3's
    # through the agent (n1's ranks are mpirun's own children).
    export RT_CLUSTER_AGENT_LOG=$WORK/agent.log
    placement "$(hostfile once "n1 slots=1" "n2 slots=1" "n3 slots=1")" 3 >/dev/null
    check_eq "the launch agent started the daemons on" "$(cut -d: -f1 "$WORK/agent.log" | sort | tr '\n' ' ')" "n2 n3 "
    ;;

mixed)
    # A site's per-node defaults: the box-test path and the thread count.
    cluster_setenv n1 RT_ACCEL=bvh-sse OMP_NUM_THREADS=2
    cluster_setenv n2 RT_ACCEL=bvh-scalar OMP_NUM_THREADS=1
    cluster_setenv n3 OMP_NUM_THREADS=3
    one=$(hostfile one "n1 slots=1" "n2 slots=1" "n3 slots=1")
    # What a rank started on each host uses: a one-rank job placed there
    # (started by that host's orted like every rank of the mixed job) prints
    # rank 0's intersector and thread count.
    for h in n1 n2 n3; do
        cmpirun 60 "$one" -np 1 --host "$h" "$BIN" "${IMG[@]}" -o "$WORK/probe-$h.png" >"$WORK/probe-$h.out" 2>&1
        echo "$h: $(grep -E '^(intersector|ranks):' "$WORK/probe-$h.out" | tr -s ' ' | tr '\n' ' ')"
    done >"$WORK/probes.txt"
    note "per-host probes:"; sed 's/^/     /' "$WORK/probes.txt"
    check_eq "n1's ranks use the SSE2 box test" "$(grep -o '^n1: intersector: bvh-sse (sse2 box test' "$WORK/probes.txt")" \
        "n1: intersector: bvh-sse (sse2 box test"
    check_eq "n2's ranks use the portable box test" \
        "$(grep -o '^n2: intersector: bvh-scalar (portable box test' "$WORK/probes.txt")" "n2: intersector: bvh-scalar (portable box test"
    check_eq "threads per rank on n1, n2, n3" \
        "$(sed -n 's/^\(n[0-9]\):.*ranks: 1 x \([0-9]*\) threads.*/\1=\2/p' "$WORK/probes.txt" | tr '\n' ' ')" "n1=2 n2=1 n3=3 "
    hf=$(hostfile mixed "n1 slots=1" "n2 slots=2" "n3 slots=1")
    check_eq "mixed: ranks per host" "$(placement "$hf" 4)" "n1:1 n2:2 n3:1"
    cmpirun 120 "$hf" -np 4 "$BIN" "${IMG[@]}" -o "$WORK/mixed.png" >"$WORK/mixed.out" 2>&1
    check_eq "mixed: exit status" $? 0
    same_image "mixed (n1 bvh-sse x2 threads, n2 2 ranks bvh-scalar x1, n3 default x3)" "$WORK/mixed.png" ||
        show "$WORK/mixed.out"
    # The same with the scalar host first: rank 0 is then on it.
    hf=$(hostfile mixed2 "n2 slots=1" "n1 slots=2" "n3 slots=1")
    cmpirun 120 "$hf" -np 4 "$BIN" "${IMG[@]}" -o "$WORK/mixed2.png" >"$WORK/mixed2.out" 2>&1
    check_eq "mixed, rank 0 on the scalar host: exit status" $? 0
    same_image "mixed, rank 0 on the scalar host" "$WORK/mixed2.png" || show "$WORK/mixed2.out"
    # A frame job over the same mixed hosts (units of several frames in
    # flight, each rank building each frame's camera itself): every frame
    # is the bytes of the one-process build's --frame N alone. The final
    # scene on a turntable, and book 2's moving spheres (a ray's time).
    for sc in "turn --turntable 90:4" "bounce --scene bouncing-spheres --max-depth 8"; do
        read -r tag args <<<"$sc"
        # shellcheck disable=SC2086
        cmpirun 120 "$hf" -np 4 "$BIN" "${IMG[@]}" $args --frames 0-2 -o "$WORK/$tag-#.png" >"$WORK/$tag.out" 2>&1
        check_eq "mixed, frames ($tag): exit status" $? 0
        same=0
        for f in 0 1 2; do
            # shellcheck disable=SC2086
            "$SERIAL" "${IMG[@]}" $args -j 2 --frame $f -o "$WORK/$tag-ref-#.png" >/dev/null 2>&1 &&
                cmp -s "$WORK/$tag-$f.png" "$WORK/$tag-ref-$f.png" && same=$((same + 1))
        done
        check_eq "mixed, frames ($tag): frames identical to the one-process --frame N" $same 3
    done
    ;;

badnet)
    hf=$(hostfile six "n1 slots=2" "n2 slots=2" "n3 slots=2")
    BIG=(--width 160 --height 100 -s 16 --no-checkpoint -q)
    "$SERIAL" "${BIG[@]}" -j 2 -o "$WORK/ref16.png" >/dev/null
    REF=$WORK/ref16.png
    t=$(now)
    cmpirun 120 "$hf" -np 6 "$BIN" "${BIG[@]}" -j 1 -o "$WORK/clean.png" >"$WORK/clean.out" 2>&1
    check_eq "clean network: exit status" $? 0
    t_clean=$(secs "$t" "$(now)")
    same_image "clean network" "$WORK/clean.png"
    how=$(cluster_badlink n3 20 5 1) || fail "could not degrade n3's link"
    note "n3's link: 20 ms +- 5 ms delay, 1 % loss, by $how"
    t=$(now)
    cmpirun 240 "$hf" -np 6 "$BIN" "${BIG[@]}" -j 1 -o "$WORK/bad.png" >"$WORK/bad.out" 2>&1
    check_eq "bad network: exit status" $? 0
    t_bad=$(secs "$t" "$(now)")
    same_image "bad network on n3" "$WORK/bad.png" || show "$WORK/bad.out"
    [[ -f $RT_CLUSTER/badlink-n3.log ]] && note "badlink.py: $(tail -n 1 "$RT_CLUSTER/badlink-n3.log")"
    note "mpirun wall time, 6 ranks on 3 hosts, 160x100 16 spp: clean ${t_clean} s, n3 degraded ${t_bad} s" \
        "(x$(awk -v a="$t_clean" -v b="$t_bad" 'BEGIN {printf "%.2f", b / a}'))"
    ;;

losthost | lostsurvive)
    # lostsurvive: the same under mpirun --enable-recovery, where the
    # survivors must finish by themselves (exit 0, the same bytes).
    RECOVER=() LEASE=()
    [[ $CASE == lostsurvive ]] && RECOVER=(--enable-recovery) LEASE=(--lease 2)
    hf=$(hostfile six "n1 slots=2" "n2 slots=2" "n3 slots=2")
    LIMIT=${RT_CLUSTER_LOST_LIMIT:-30}
    # Long enough that n3 dies mid-render (a job of about 6 s on an idle
    # 2-core box; 1500 spp, 2 s since sampling version 4, was sometimes done
    # before the kill); a checkpoint every second.
    LONG=(--width 160 --height 100 -s 4000 -q)
    out=$WORK/lost.png
    cmpirun 300 "$hf" "${RECOVER[@]}" -np 6 "$BIN" "${LONG[@]}" "${LEASE[@]}" -j 1 -o "$out" --checkpoint-interval 1 \
        >"$WORK/lost.out" 2>&1 &
    job=$!
    for ((i = 0; i < 300; i++)); do [[ -s $out.ckpt ]] && break; sleep 0.1; done
    [[ -s $out.ckpt ]] || fail "no checkpoint within 30 s of the start"
    # killed as soon as the first checkpoint shows it rendering: no fixed
    # sleep, so the job (about 6 s of work on an idle 2-core box) is far
    # from done whatever the machine's speed
    t=$(now)
    if [[ $CASE == lostsurvive ]]; then
        # The ranks only: Open MPI 4.1's mpirun aborts the job when it loses
        # an orted, --enable-recovery or not ("ORTE was unable to reliably
        # start one or more daemons"), so a whole host is not survivable
        # with it (losthost); a host's ranks dying (crash, OOM killer) is.
        victims=0
        for p in $(ip netns pids "$(cat "$RT_CLUSTER/hosts/n3.net")"); do
            [[ $(cat "/proc/$p/comm" 2>/dev/null) == rt-mpi ]] && kill -KILL "$p" && victims=$((victims + 1))
        done
        note "killed the $victims rt-mpi ranks on n3 (its orted lives)"
        ((victims == 2)) || fail "n3 ran $victims ranks, not 2"
    else
        victims=$(ip netns pids "$(cat "$RT_CLUSTER/hosts/n3.net")" | wc -l)
        cluster_kill n3 KILL
        note "killed the $victims processes on n3 (orted and its ranks)"
    fi
    ended=""
    for ((i = 0; i < LIMIT * 10; i++)); do
        kill -0 "$job" 2>/dev/null || { ended=1; break; }
        # lostsurvive: the render is done when the image is there; mpirun
        # itself may not end (below)
        [[ $CASE == lostsurvive && -s $out && ! -e $out.ckpt ]] && break
        sleep 0.1
    done
    took=$(secs "$t" "$(now)")
    if [[ $CASE == lostsurvive && -z $ended && -s $out ]]; then
        pass "the survivors finished the image ${took} s after n3's ranks were lost"
        grep -q "^lost ranks: *2" "$WORK/lost.out" && pass "the summary counts n3's 2 ranks lost" ||
            fail "lost ranks: $(grep -m1 lost "$WORK/lost.out")"
        "$SERIAL" "${LONG[@]}" --no-checkpoint -j 2 -o "$WORK/ref-long.png" >/dev/null
        REF=$WORK/ref-long.png
        same_image "lost ranks, finished by the survivors" "$out"
        # Known limit of Open MPI 4.1 across hosts: rank 0's MPI_Abort(.., 0)
        # after the image ends a one-host job (e2e_survival), but here
        # mpirun fails in its own help output ("ORTE_ERROR_LOG: Out of
        # resource in show_help.c") and does not exit. Said, not passed.
        for ((i = 0; i < 100; i++)); do kill -0 "$job" 2>/dev/null || { ended=1; break; }; sleep 0.1; done
        if [[ -n $ended ]]; then
            wait "$job"
            note "mpirun ended by itself (exit $?)"
        else
            note "KNOWN LIMIT: mpirun did not end 10 s after the image (Open MPI 4.1 ORTE across hosts); ending it"
            cluster_kill n1 KILL
            cluster_kill n2 KILL
            cluster_kill n3 KILL
            wait "$job"
        fi
        finish
    fi
    if [[ -z $ended ]]; then
        fail "the job did not end within $LIMIT s of losing n3 (a hang)"
        cluster_kill n1 KILL
        cluster_kill n2 KILL
        wait "$job"
        show "$WORK/lost.out"
        finish
    fi
    wait "$job"
    rc=$?
    pass "the job ended ${took} s after n3 was lost (exit $rc)"
    "$SERIAL" "${LONG[@]}" --no-checkpoint -j 2 -o "$WORK/ref-long.png" >/dev/null
    REF=$WORK/ref-long.png
    if ((rc == 0)); then
        note "outcome: the survivors finished the render by themselves"
        same_image "lost host, finished by the survivors" "$out"
        grep -q "^lost ranks: *2" "$WORK/lost.out" && pass "the summary counts n3's 2 ranks lost" ||
            fail "lost ranks: $(grep -m1 lost "$WORK/lost.out")"
    elif [[ $CASE == lostsurvive ]]; then
        fail "under --enable-recovery the job must finish by itself: exit $rc"
        show "$WORK/lost.out"
    elif [[ -s $out.ckpt ]]; then
        note "outcome: exit $rc with a checkpoint; resuming on n1 and n2"
        show "$WORK/lost.out" | grep -m 3 -E 'rt-mpi|checkpoint'
        hf2=$(hostfile two "n1 slots=2" "n2 slots=2")
        cmpirun 300 "$hf2" -np 4 "$BIN" "${LONG[@]}" -j 1 -o "$out" --resume >"$WORK/resume.out" 2>&1
        check_eq "resume on the hosts left: exit status" $? 0
        r=$(grep -o '[0-9.]*% of the samples restored' "$WORK/resume.out")
        [[ -n $r ]] && pass "resume restored $r" || fail "resume restored nothing: $(head -c 300 "$WORK/resume.out")"
        same_image "lost host, resumed" "$out" || show "$WORK/resume.out"
    else
        fail "exit $rc and no checkpoint to resume from"
        show "$WORK/lost.out"
    fi
    ;;

slurm | slurmlost)
    source "$HERE/slurm_cluster.sh"
    trap 'cslurm_down; cluster_down; rm -rf "$WORK"' EXIT
    t=$(now)
    cslurm_up >"$WORK/cslurm_up.txt" ||
        { fail "Slurm on the cluster did not come up: $(cat "$WORK/cslurm_up.txt")"; cslurm_logs; finish; }
    note "slurmctld on n1, slurmd on n1 n2 n3: idle after $(secs "$t" "$(now)") s"
    # What the jobs inherit (sbatch exports the submitting environment):
    # TCP between hosts on the cluster network only.
    export OMPI_MCA_btl_tcp_if_include=$NET OMPI_MCA_oob_tcp_if_include=$NET OMPI_MCA_btl=self,vader,tcp
    export RT_MPI_BIN=$BIN
    SCRIPT=$HERE/../../scripts/slurm/rt-mpi.sbatch
    field() { cslurm n1 scontrol -o show job "$1" 2>/dev/null | tr ' ' '\n' | sed -n "s/^$2=//p"; }
    wait_done() { # job seconds -> state in JOB_STATE
        local i
        for ((i = 0; i < $2 * 4; i++)); do
            JOB_STATE=$(field "$1" JobState)
            case $JOB_STATE in COMPLETED | FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY) return 0 ;; esac
            sleep 0.25
        done
        return 1
    }
    submit() { # name sbatch-args... -> job id
        local name=$1
        shift
        RT_OUTPUT="$WORK/$name.png" cslurm n1 timeout 30 sbatch --parsable --chdir="$WORK" \
            --output="$WORK/$name-%j.out" "$@"
    }
    # Open MPI 4.1's TCP transport crashes a rank now and then when srun
    # starts the job here (a call through a null handler; 1 job in 10 to
    # 30, also with tools/mpi_startup.c, which has no rt-mpi code:
    # docs/notes/farm.md). A job that failed with that crash's own report
    # is submitted once more, and said so; any other failure, or the crash
    # twice, fails the test.
    ompi_null_crash() { grep -q 'Failing at address: (nil)' "$1" && grep -q 'Segmentation fault' "$1"; }
    if [[ $CASE == slurmlost ]]; then
        # Every process of n3 (slurmd, slurmstepd, ranks) killed mid-render
        # of a job launched with srun (--no-kill in the script): the other
        # ranks finish the image, and the script exits 0 on rank 0's done
        # file although srun reports the dead tasks. Slurm itself waits for
        # the dead node a long time, so the job's log is what is checked.
        # (4000 spp: about 6 s of work, far from done at the first checkpoint)
        LONG=(--width 160 --height 100 -s 4000)
        "$SERIAL" "${LONG[@]}" -q --no-checkpoint -j 2 -o "$WORK/ref-long.png" >/dev/null
        REF=$WORK/ref-long.png
        out=$WORK/lostnode.png
        for try in 1 2; do
            j=$(RT_LAUNCHER=srun RT_WIDTH=160 RT_HEIGHT=100 RT_SAMPLES=4000 RT_ARGS="-q --lease 4 --checkpoint-interval 1" \
                submit lostnode -N 3 --ntasks-per-node=2 -c 1 "$SCRIPT") || { fail "sbatch -N 3 (srun) refused"; finish; }
            for ((i = 0; i < 600; i++)); do
                [[ -s $out.ckpt ]] && break
                ((i % 10 == 9)) && [[ $(field "$j" JobState) == FAILED ]] && break # died before its first checkpoint
                sleep 0.1
            done
            [[ ! -s $out.ckpt && $try == 1 && $(field "$j" JobState) == FAILED ]] &&
                ompi_null_crash "$WORK/lostnode-$j.out" || break
            note "job $j hit Open MPI's TCP crash before its first checkpoint (job output below); submitting it once more"
            show "$WORK/lostnode-$j.out" 12
        done
        [[ -s $out.ckpt ]] || { fail "job $j: no checkpoint within 60 s of the start (state $(field "$j" JobState))"; show "$WORK/lostnode-$j.out"; finish; }
        t=$(now)
        victims=$(ip netns pids "$(cat "$RT_CLUSTER/hosts/n3.net")" | wc -l)
        cluster_kill n3 KILL
        # what slurmctld does once n3 is silent for SlurmdTimeout (300 s
        # here): without --no-kill that ends the job (NODE_FAIL)
        cslurm n1 scontrol update NodeName=n3 State=DOWN Reason=rt-mpi-test
        note "job $j: killed the $victims processes on n3 (slurmd, its step, its ranks); n3 set DOWN"
        log=$WORK/lostnode-$j.out
        for ((i = 0; i < 240; i++)); do grep -q "done: $out" "$log" 2>/dev/null && break; sleep 0.25; done
        if grep -q "done: $out" "$log"; then
            pass "job $j: the script finished the render $(secs "$t" "$(now)") s after n3 was lost"
        else
            fail "job $j: no 'done' in its log 60 s after n3 was lost"
        fi
        grep -q "the launcher exited with [1-9][0-9]*, but rank 0 finished the image" "$log" &&
            pass "job $j: srun's failure status was overruled by rank 0's done file" ||
            note "srun exited 0 by itself"
        grep -q "^rank [45]: .*on n3 (lost at" "$log" && pass "job $j: the summary names n3's ranks lost" ||
            fail "job $j: n3's ranks not reported lost: $(grep -m2 'lost' "$log")"
        same_image "lost node under srun" "$out" || show "$log"
        finish
    fi
    for l in srun mpirun; do
        t=$(now)
        for try in 1 2; do
            j=$(RT_LAUNCHER=$l RT_WIDTH=160 RT_HEIGHT=100 RT_SAMPLES=4 RT_ARGS=-q \
                submit "N3-$l" -N 3 --ntasks-per-node=2 -c 1 "$SCRIPT") || break
            wait_done "$j" 120 || break
            [[ $try == 1 && $l == srun && $JOB_STATE == FAILED ]] && ompi_null_crash "$WORK/N3-$l-$j.out" ||
                break
            note "sbatch -N 3 ($l): job $j hit Open MPI's TCP crash (job output below); submitting it once more"
            show "$WORK/N3-$l-$j.out" 12
        done
        [[ -n $j ]] || { fail "sbatch -N 3 ($l) refused"; continue; }
        if [[ ! $JOB_STATE =~ ^(COMPLETED|FAILED|CANCELLED|TIMEOUT|NODE_FAIL|OUT_OF_MEMORY)$ ]]; then
            fail "sbatch -N 3 ($l): job $j not done after 120 s (state $JOB_STATE)"; show "$WORK/N3-$l-$j.out"; continue
        fi
        got="$JOB_STATE $(field "$j" ExitCode) $(field "$j" NodeList)"
        check_eq "sbatch -N 3 ($l): job $j state, exit code, nodes" "$got" "COMPLETED 0:0 n[1-3]"
        if [ "$got" != "COMPLETED 0:0 n[1-3]" ]; then # what the job and each slurmd said about it
            show "$WORK/N3-$l-$j.out" 80
            grep -hE "(StepId=|\[)$j\.|JobId=$j( |$)" "$RT_CLUSTER"/slurm/log/slurmd-*.log 2>/dev/null | tail -n 20 |
                sed 's/^/     | /'
        fi
        note "sbatch -N 3 --ntasks-per-node=2 ($l): $(secs "$t" "$(now)") s submit to done"
        same_image "sbatch -N 3 ($l)" "$WORK/N3-$l.png" || show "$WORK/N3-$l-$j.out"
    done

    # The time-limit warning (SIGUSR1 to the batch shell, as --signal=B:USR1@N
    # sends it; tests/slurm/NOTES.md says why not a real time limit): the
    # renderer checkpoints and exits 75, the script requeues the job, and
    # the first node it ran on is drained meanwhile, so it resumes on others.
    LONG=(--width 160 --height 100 -s 1500)
    "$SERIAL" "${LONG[@]}" -q --no-checkpoint -j 2 -o "$WORK/ref-long.png" >/dev/null
    REF=$WORK/ref-long.png
    ckpt=$WORK/requeue.png.ckpt
    j=$(RT_LAUNCHER=mpirun RT_CHECKPOINT=$ckpt RT_WIDTH=160 RT_HEIGHT=100 RT_SAMPLES=1500 \
        RT_ARGS="-q --checkpoint-interval 0" submit requeue -N 2 --ntasks-per-node=1 -c 2 "$SCRIPT") ||
        { fail "sbatch -N 2 (requeue) refused"; finish; }
    for ((i = 0; i < 600; i++)); do
        [[ -s $ckpt ]] && break
        ((i % 10 == 9)) && [[ ! $(field "$j" JobState) =~ ^(PENDING|CONFIGURING|RUNNING)$ ]] && break
        sleep 0.1
    done
    first=$(field "$j" NodeList) st=$(field "$j" JobState)
    if [[ ! -s $ckpt || $st != RUNNING ]]; then
        fail "requeue: job $j is $st, checkpoint $( [[ -s $ckpt ]] && echo present || echo missing) (too short to interrupt?)"
        show "$WORK/requeue-$j.out"
    else
        cslurm n1 scancel --signal=USR1 --batch "$j"
        drained=$(cslurm n1 scontrol show hostnames "$first" | head -n 1)
        cslurm n1 scontrol update NodeName="$drained" State=DRAIN Reason=rt-mpi-test
        note "requeue: job $j ran on $first: SIGUSR1 sent, $drained drained"
        wait_done "$j" 180 || fail "requeue: job $j not done 180 s after the signal (state $JOB_STATE)"
        check_eq "requeue: state, exit code" "$JOB_STATE $(field "$j" ExitCode)" "COMPLETED 0:0"
        restarts=$(field "$j" Restarts) last=$(field "$j" NodeList)
        ((restarts >= 1)) && pass "requeue: $restarts restart(s); ran on $first, then on $last" ||
            fail "requeue: no restart (Restarts=$restarts)"
        [[ $last != "$first" ]] && pass "requeue: resumed on other nodes ($first -> $last)" ||
            fail "requeue: resumed on the same nodes $last although $drained was drained"
        grep -q 'renderer exited with 75' "$WORK/requeue-$j.out" && grep -q 'found: resuming' "$WORK/requeue-$j.out" &&
            pass "requeue: exit 75 with a checkpoint, then --resume" ||
            fail "requeue: no exit 75 / resume in the job's log"
        same_image "requeue (resumed on $last)" "$WORK/requeue.png" || show "$WORK/requeue-$j.out"
        cslurm n1 scontrol update NodeName="$drained" State=RESUME
    fi
    ((FAILED > 0)) && cslurm_logs
    ;;

*)
    echo "unknown case '$CASE'" >&2
    exit 2 ;;
esac
note "done"
finish
