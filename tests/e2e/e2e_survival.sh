#!/bin/bash
# e2e_survival.sh BIN MPIRUN HOOKS - a lost rank costs no restart. Under
# `mpirun --enable-recovery` (Open MPI 4.1 has no ULFM; with it the
# survivors keep talking), one worker is killed (kill -9) or hung (SIGSTOP)
# mid-render: rank 0 hears nothing from it for a lease, hands its units to
# the others, and the job ends by itself with status 0 and the bytes of an
# uninterrupted run. (Without --enable-recovery mpirun ends the whole job:
# e2e_resume.sh checks the checkpoint and --resume for that case.)
BIN=$1 MPIRUN=${2:-} HOOKS=${3:-}
source "$(dirname "$0")/../support/lib.sh"
[ -n "$MPIRUN" ] || { skip "no mpirun"; finish; }
K=(--width 160 --height 96 -s 2400 -q)
"$BIN" "${K[@]}" -j 2 --no-checkpoint -o "$WORK/ref.png" >"$WORK/ref.out" 2>&1
check_eq "reference render" $? 0

same_image() { cmp -s "$1" "$WORK/ref.png"; }

# lose_rank label signal rank [options]
lose_rank() {
    local label=$1 sig=$2 rank=$3 out="$WORK/$1.png"
    shift 3
    stop_rank_during "$label" "$sig" "$rank" "$out" "same_image $out" -- \
        timeout 120 "$MPIRUN" --enable-recovery -np 3 --bind-to none "$BIN" "${K[@]}" -j 1 --lease 2 -o "$out" \
        --done-file "$WORK/$label.done" "$@"
    [ -n "$victim" ] || return
    check_eq "$label: exit status of mpirun" $status 0
    cmp -s "$out" "$WORK/ref.png" && pass "$label: image identical to the uninterrupted render" ||
        fail "$label: image differs or is missing"
    grep -q "rank $rank lost" "$WORK/$label.err" && pass "$label: rank 0 says rank $rank was lost" ||
        fail "$label: no loss reported: $(grep -m2 rt-mpi "$WORK/$label.err")"
    grep -q "^lost ranks: *1" "$WORK/$label.out" && pass "$label: the summary counts the lost rank" ||
        fail "$label: summary: $(grep -m1 lost "$WORK/$label.out")"
    # --done-file (what a job script reads when the launcher reports the
    # dead rank as a failure): done, the image's hash, one rank lost
    check_eq "$label: --done-file" "$(cat "$WORK/$label.done" 2>&1)" \
        "done $(sed -n 's/^image hash: *//p' "$WORK/$label.out") lost 1 $out"
    # The summary says when and what the loss cost: silent for at least
    # the 2 s lease, some units handed on, and the seconds of rendering the
    # rank had finished but not sent: none is lost with 0.1 s flushes
    # (only what was in hand), with --flush-interval 3600 about the CPU
    # time it had used (rendering takes at least its CPU time), and never
    # more than the time it ran.
    local cost at silent units redone
    cost=$(sed -n "s/^rank $rank: .*(lost at \([0-9.]*\) s, silent for \([0-9.]*\) s: \([0-9]*\) units and \([0-9.]*\) s.*/\1 \2 \3 \4/p" \
        "$WORK/$label.out")
    read -r at silent units redone <<<"$cost"
    [[ -n $cost ]] && awk -v s="$silent" -v a="$at" -v u="$units" 'BEGIN {exit !(s >= 2 && a >= s && u > 0)}' &&
        pass "$label: rank $rank lost at $at s, silent for $silent s, $units units went to the others" ||
        fail "$label: the summary's cost of the loss: '$(grep "^rank $rank:" "$WORK/$label.out")'"
    if [ "$HELD" = held ]; then
        # more units than a rank has in hand (2): finished ones came back
        [[ -n $cost ]] && awk -v r="$redone" -v c="$cpu" -v a="$at" -v u="$units" \
            'BEGIN {exit !(u > 2 && r >= c / 2 && r <= a)}' &&
            pass "$label: $units units and $redone s of finished, unsent rendering were lost (rank $rank had used $cpu s of CPU; lost at $at s)" ||
            fail "$label: finished, unsent work lost: $units units, '$redone' s, against $cpu s of CPU, lost at '$at' s"
    fi
    [ $status -ne 0 ] || { [ ! -e "$out.ckpt" ] && pass "$label: checkpoint removed after success" ||
        fail "$label: checkpoint left"; }
    pgrep -f -- "-o $out" >/dev/null && { fail "$label: processes left behind"; pkill -9 -f -- "-o $out"; } ||
        pass "$label: no process left behind"
}
# A killed rank that holds the sums of finished units (it sends them only
# every hour): rank 0 hands those units out again too.
HELD=held lose_rank kill9 KILL 1 --flush-interval 3600
HELD= lose_rank hung STOP 2

# A frame job (units of several frames in flight at once): a killed rank's
# units, whichever frames they belong to, go to the others, and every
# frame is the bytes of an uninterrupted range.
F=(--width 160 --height 96 -s 600 -q --turntable 90:4 --frames 0-3)
"$BIN" "${F[@]}" -j 2 --no-checkpoint -o "$WORK/fref_#.png" >"$WORK/fref.out" 2>&1
check_eq "frames: reference range" $? 0
same_frames() { local f; for f in 0 1 2 3; do cmp -s "$WORK/fr_$f.png" "$WORK/fref_$f.png" || return 1; done; }
stop_rank_during fr KILL 1 "$WORK/fr_#.png" same_frames -- \
    timeout 120 "$MPIRUN" --enable-recovery -np 3 --bind-to none "$BIN" "${F[@]}" -j 1 --lease 2 \
    --flush-interval 3600 -o "$WORK/fr_#.png"
check_eq "frames: exit status of mpirun" $status 0
grep -q "rank 1 lost" "$WORK/fr.err" && pass "frames: rank 0 says rank 1 was lost" ||
    fail "frames: no loss reported: $(grep -m2 rt-mpi "$WORK/fr.err")"
same=0
for f in 0 1 2 3; do cmp -s "$WORK/fr_$f.png" "$WORK/fref_$f.png" && same=$((same + 1)); done
check_eq "frames: frames identical to the uninterrupted range" $same 4
pgrep -f -- "-o $WORK/fr_#.png" >/dev/null && { fail "frames: processes left behind"; pkill -9 -f -- "-o $WORK/fr_#.png"; } ||
    pass "frames: no process left behind"

# A rank lost before rendering began (the test build's rank 1 kills itself
# before the start-up's last collective): the others cannot go on without
# it there, and must not wait forever either (nothing else ends an
# --enable-recovery job): rank 0 ends the job with one line after the
# start-up wait (3 s here, RT_POLICY_START_WAIT otherwise), and nothing is
# written. Open MPI 4.1's mpirun --enable-recovery reports 0 even after
# MPI_Abort, so the missing --done-file is the job script's outcome.
if [ -n "$HOOKS" ]; then
    out="$WORK/start.png"
    RT_TEST_DIE_AT_START=1 RT_TEST_START_WAIT=3 timeout 60 "$MPIRUN" -x RT_TEST_DIE_AT_START -x RT_TEST_START_WAIT \
        --enable-recovery -np 3 --bind-to none "$HOOKS" "${K[@]}" -j 1 --lease 2 -o "$out" \
        --done-file "$WORK/start.done" >"$WORK/start.out" 2>"$WORK/start.err"
    status=$?
    [ $status -ne 124 ] && pass "start: the job ended by itself (mpirun status $status)" ||
        fail "start: still waiting after 60 s"
    check_eq "start: rank 0's one line" \
        "$(grep -c "^rt-mpi: error: rank 0: not every rank reached the start-up's .* within 3 s: a rank was lost" \
            "$WORK/start.err")" 1
    [ ! -e "$out" ] && [ ! -e "$WORK/start.done" ] && pass "start: no image, no --done-file" ||
        fail "start: $(ls "$WORK"/start.*)"
    pgrep -f -- "-o $out" >/dev/null && { fail "start: processes left behind"; pkill -9 -f -- "-o $out"; } ||
        pass "start: no process left behind"
else
    skip "start: no test build"
fi
finish
