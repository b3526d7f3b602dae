#!/bin/bash
# e2e_survival.sh BIN MPIRUN - a lost rank costs no restart. Under
# `mpirun --enable-recovery` (Open MPI 4.1 has no ULFM; with it the
# survivors keep talking), one worker is killed (kill -9) or hung (SIGSTOP)
# mid-render: rank 0 hears nothing from it for a lease, hands its units to
# the others, and the job ends by itself with status 0 and the bytes of an
# uninterrupted run. (Without --enable-recovery mpirun ends the whole job:
# e2e_resume.sh checks the checkpoint and --resume for that case.)
BIN=$1 MPIRUN=${2:-}
source "$(dirname "$0")/../support/lib.sh"
[ -n "$MPIRUN" ] || { skip "no mpirun"; finish; }
K=(--width 160 --height 96 -s 2400 -q)
"$BIN" "${K[@]}" -j 2 --no-checkpoint -o "$WORK/ref.png" >"$WORK/ref.out" 2>&1
check_eq "reference render" $? 0
# The same job without a loss, timed as the lossy ones are.
t0=$(date +%s.%N)
timeout 120 "$MPIRUN" -np 3 --bind-to none "$BIN" "${K[@]}" -j 1 -o "$WORK/whole.png" >/dev/null 2>&1
check_eq "the job without a loss" $? 0
whole=$(echo "$(date +%s.%N) - $t0" | bc)

lose_rank() { # label signal rank
    local label=$1 sig=$2 rank=$3 out="$WORK/$1.png"
    local t0 victim
    t0=$(date +%s.%N)
    timeout 120 "$MPIRUN" --enable-recovery -np 3 --bind-to none "$BIN" "${K[@]}" -j 1 --lease 2 -o "$out" \
        --done-file "$WORK/$label.done" \
        >"$WORK/$label.out" 2>"$WORK/$label.err" &
    local pid=$!
    victim=$(rank_pid "-o $out" "$rank")
    [ -n "$victim" ] || { fail "$label: rank $rank not found"; kill $pid; wait $pid; return; }
    sleep 1.5 # mid-render: the whole job takes about 4 s here
    kill -"$sig" "$victim"
    wait $pid
    local status=$? took
    took=$(echo "$(date +%s.%N) - $t0" | bc)
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
    # the summary says when and what the loss cost: silent for at least
    # the 2 s lease, some units handed on
    local cost
    cost=$(sed -n "s/^rank $rank: .*(lost at \([0-9.]*\) s, silent for \([0-9.]*\) s: \([0-9]*\) units.*/\1 \2 \3/p" \
        "$WORK/$label.out")
    read -r at silent units <<<"$cost"
    [[ -n $cost ]] && awk -v s="$silent" -v a="$at" -v u="$units" 'BEGIN {exit !(s >= 2 && a >= s && u > 0)}' &&
        pass "$label: rank $rank lost at $at s, silent for $silent s, $units units went to the others" ||
        fail "$label: the summary's cost of the loss: '$(grep "^rank $rank:" "$WORK/$label.out")'"
    echo "  $label: ${took} s wall with the loss against ${whole} s without: $(echo "$took - $whole" | bc) s lost (lease 2 s)"
    [ $status -ne 0 ] || { [ ! -e "$out.ckpt" ] && pass "$label: checkpoint removed after success" ||
        fail "$label: checkpoint left"; }
    pgrep -f -- "-o $out" >/dev/null && { fail "$label: processes left behind"; pkill -9 -f -- "-o $out"; } ||
        pass "$label: no process left behind"
}
lose_rank kill9 KILL 1
lose_rank hung STOP 2
finish
