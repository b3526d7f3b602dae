#!/bin/bash
# e2e_resume.sh BIN MPIRUN
# Checkpoint and resume: a run stopped by SIGTERM / SIGUSR1 (also through
# mpirun), or by a worker killed with -9, leaves a valid checkpoint, and
# --resume ends with the byte-identical image. Checkpoints of other jobs
# and corrupt ones are refused; a full disk gives a clear error and no file.
BIN=$1 MPIRUN=${2:-}
source "$(dirname "$0")/../support/lib.sh"
A=(--width 160 --height 96 -s 1000 -q)
"$BIN" "${A[@]}" -j 2 -o "$WORK/ref.png" --stats "$WORK/ref.json" >/dev/null
check_eq "reference render" $? 0

wait_for_file() { # file seconds
    local i
    for ((i = 0; i < $2 * 10; i++)); do [ -s "$1" ] && return 0; sleep 0.1; done
    return 1
}
# stop_and_resume label signal launcher... : start, wait for the first
# checkpoint, signal the launcher, expect 75 (or mpirun's code), resume.
stop_and_resume() {
    local label=$1 sig=$2 want=$3
    shift 3
    local out="$WORK/$label.png"
    rm -f "$out" "$out.ckpt"
    "$@" "${A[@]}" -o "$out" --checkpoint-interval 0 >/dev/null 2>"$WORK/$label.err" &
    local pid=$!
    if ! wait_for_file "$out.ckpt" 60; then
        fail "$label: no checkpoint appeared"
        kill -9 $pid 2>/dev/null
        return
    fi
    kill -"$sig" $pid
    wait $pid
    check_eq "$label: exit status after SIG$sig" $? "$want"
    grep -q "interrupted by signal" "$WORK/$label.err" && pass "$label: says it was interrupted" ||
        fail "$label: no interruption message: $(head -c 300 "$WORK/$label.err")"
    [ ! -e "$out" ] && pass "$label: no partial image" || fail "$label: image written by an interrupted run"
    "$BIN" "${A[@]}" -j 2 -o "$out" --resume --stats "$WORK/$label.json" >"$WORK/$label.out" 2>&1
    check_eq "$label: resume exit status" $? 0
    rendered_only_missing "$label" "$WORK/$label.out" "$WORK/$label.json" "$WORK/ref.json"
    cmp -s "$out" "$WORK/ref.png" && pass "$label: resumed image identical" || fail "$label: resumed image differs"
    [ ! -e "$out.ckpt" ] && pass "$label: checkpoint removed after success" || fail "$label: checkpoint left"
}
stop_and_resume serial-term TERM 75 "$BIN" -j 2
stop_and_resume serial-int INT 75 "$BIN" -j 1
# Progressive passes: rows are stopped with part of their samples; the
# resume (without passes) adds the rest.
stop_and_resume passes-term TERM 75 "$BIN" -j 2 --passes 5
if [ -n "$MPIRUN" ]; then
    stop_and_resume mpi-usr1 USR1 75 "$MPIRUN" -np 2 --oversubscribe --bind-to none "$BIN" -j 1
    # SIGTERM to mpirun: Open MPI ends the job itself (exit 1), but rank 0
    # still saves the checkpoint first.
    stop_and_resume mpi-term TERM 1 "$MPIRUN" -np 3 --oversubscribe --bind-to none "$BIN" -j 1

    # A worker killed with -9: the job ends within seconds. No periodic
    # checkpoint is due (interval 1 h), so a checkpoint can only come from
    # rank 0 saving on the SIGTERM mpirun sends it; the resume is identical.
    # A job four times as long as A, so it still runs when the kill comes
    # (A takes about 1.5 s here under mpirun: a faster renderer once
    # finished it first).
    K=(--width 160 --height 96 -s 4000 -q)
    "$BIN" "${K[@]}" -j 2 -o "$WORK/ref4.png" --stats "$WORK/ref4.json" >/dev/null
    check_eq "reference render (kill -9 job)" $? 0
    out="$WORK/kill9.png"
    # some rows complete: rank 1 has rendered for 0.5 s of CPU (again at
    # less if it had rendered its whole share by then: lib.sh)
    stop_rank_during kill9 KILL 1 "$out" "cmp -s $out $WORK/ref4.png" -- \
        "$MPIRUN" -np 2 --oversubscribe --bind-to none "$BIN" "${K[@]}" -j 1 -o "$out" --checkpoint-interval 3600
    if [ -n "$victim" ]; then
        [ $status -ne 0 ] && pass "kill -9 of rank 1 ends the job (status $status)" || fail "kill -9: status $status"
        [ -s "$out.ckpt" ] && pass "kill -9: rank 0 saved a checkpoint on mpirun's SIGTERM" ||
            fail "kill -9: no checkpoint: $(grep -m1 rt-mpi "$WORK/kill9.err")"
        "$BIN" "${K[@]}" -j 2 -o "$out" --resume --stats "$WORK/kill9.json" >"$WORK/kill9.out" 2>&1
        rendered_only_missing "kill -9" "$WORK/kill9.out" "$WORK/kill9.json" "$WORK/ref4.json"
        cmp -s "$out" "$WORK/ref4.png" && pass "kill -9: resumed image identical" ||
            fail "kill -9: resume: $(head -c 300 "$WORK/kill9.out")"
    fi
else
    skip "mpirun cases: no mpirun"
fi

# A frame job stopped in its third frame: --resume leaves the written
# frames alone (same inode and time: not rendered or written again),
# continues the frame in flight from the checkpoint's sums (fewer ray
# segments than that frame alone) and renders the rest; every frame
# identical to an uninterrupted run. The checkpoint (format 8) lists its
# frames in flight: their count at offset 96, the rows with samples at 112,
# their numbers from 116, then each frame's row counts.
F=(--width 160 --height 96 -s 300 --turntable 60:4 -q -j 2)
"$BIN" "${F[@]}" --frames 0-3 -o "$WORK/fref_#.png" --stats "$WORK/fref_#.json" --no-checkpoint >/dev/null
check_eq "frame job reference" $? 0
ckpt_u32() { od -An -tu4 -j "$2" -N4 "$1" 2>/dev/null | tr -d ' '; } # file offset
"$BIN" "${F[@]}" --frames 0-3 -o "$WORK/fr_#.png" --checkpoint-interval 0 >/dev/null 2>"$WORK/fr.err" &
pid=$!
# the checkpoint's first frame in flight is 2 and some rows are in
for ((i = 0; i < 600; i++)); do
    [ "$(ckpt_u32 "$WORK/fr_#.png.ckpt" 116)" = 2 ] && [ "$(ckpt_u32 "$WORK/fr_#.png.ckpt" 112)" -gt 0 ] 2>/dev/null && break
    sleep 0.1
done
kill -TERM $pid
wait $pid
check_eq "frame job: exit status after SIGTERM" $? 75
check_eq "frame job: frames 0 and 1 written, 2 and 3 not" "$(ls "$WORK" | grep '^fr_[0-9]\.png$' | tr '\n' ' ')" "fr_0.png fr_1.png "
before=$(stat -c '%i %Y.%y' "$WORK/fr_0.png" "$WORK/fr_1.png")
"$BIN" "${F[@]}" --frames 0-3 -o "$WORK/fr_#.png" --resume --stats "$WORK/fr_#.json" >"$WORK/fr.out" 2>"$WORK/fr.err"
check_eq "frame job: resume exit status" $? 0
check_eq "frame job: written frames untouched by the resume" "$(stat -c '%i %Y.%y' "$WORK/fr_0.png" "$WORK/fr_1.png")" "$before"
segs=$(stat_of "$WORK/fr_2.json" ray_segments) all=$(stat_of "$WORK/fref_2.json" ray_segments)
[ -n "$segs" ] && [ -n "$all" ] && [ "$segs" -lt "$all" ] &&
    pass "frame job: frame 2 continued from the checkpoint ($segs of $all ray segments)" ||
    fail "frame job: frame 2 rendered again: $segs of $all ray segments"
# frame 3 may have been in flight too when the signal came: never more than whole
segs=$(stat_of "$WORK/fr_3.json" ray_segments) all=$(stat_of "$WORK/fref_3.json" ray_segments)
[ -n "$segs" ] && [ -n "$all" ] && [ "$segs" -le "$all" ] && pass "frame job: frame 3 rendered ($segs of $all ray segments)" ||
    fail "frame job: frame 3: $segs of $all ray segments"
same=0
for f in 0 1 2 3; do cmp -s "$WORK/fr_$f.png" "$WORK/fref_$f.png" && same=$((same + 1)); done
check_eq "frame job: resumed frames identical to the uninterrupted run" "$same of 4" "4 of 4"
[ ! -e "$WORK/fr_#.png.ckpt" ] && pass "frame job: checkpoint removed after the last frame" || fail "frame job: checkpoint left"

# Two frames in flight (units across frames, issue 37): stopped while two
# frames both have rows in, the checkpoint holds both (each with its counts
# and sums), and --resume continues both (fewer ray segments than each
# alone) and ends with every frame identical. Over 2 ranks, rank 1 is
# stopped (SIGSTOP) once the checkpoint has a frame in flight, with units
# of an early frame in hand: that frame stays partial while rank 0 renders the next
# frames' units (the lease is long, so rank 1 is not lost). The signal is
# sent once the checkpoint shows two partial frames, rank 1 is continued,
# and the check reads the checkpoint the stop left (the job is run again,
# at most 5 times, until it does).
if [ -n "$MPIRUN" ]; then
    P=(--width 64 --height 16 -s 600 --turntable 60:4 -q --band 2)
    "$BIN" "${P[@]}" -j 2 --frames 0-5 -o "$WORK/pref_#.png" --stats "$WORK/pref_#.json" --no-checkpoint >/dev/null
    check_eq "two in flight: reference" $? 0
    two_partial() { # checkpoint: its first two frames in flight, when both have rows in
        local c=$1 n rows a b
        n=$(ckpt_u32 "$c" 96)
        [ -n "$n" ] && [ "$n" -ge 2 ] 2>/dev/null || return 1
        a=$(od -An -tu4 -j $((116 + 4 * n)) -N 64 "$c" | tr -s ' \n' ' ' | awk '{ s = 0; for (i = 1; i <= NF; i++) s += $i; print (s > 0) }')
        b=$(od -An -tu4 -j $((116 + 4 * n + 64)) -N 64 "$c" | tr -s ' \n' ' ' | awk '{ s = 0; for (i = 1; i <= NF; i++) s += $i; print (s > 0) }')
        [ "$a" = 1 ] && [ "$b" = 1 ] && echo "$(ckpt_u32 "$c" 116) $(ckpt_u32 "$c" 120)"
    }
    got=""
    for attempt in 1 2 3 4 5; do
        [ -n "$got" ] && break
        rm -f "$WORK"/p2_* "$WORK/p2_#.png.ckpt"
        "$MPIRUN" -np 2 --oversubscribe --bind-to none "$BIN" "${P[@]}" -j 1 --frames 0-5 -o "$WORK/p2_#.png" \
            --checkpoint-interval 0 --lease 120 >/dev/null 2>"$WORK/p2.err" &
        pid=$!
        victim=$(rank_pid "-o $WORK/p2_#.png" 1)
        # as soon as the checkpoint has a frame in flight: rank 1 has held
        # units of the first frames since it said hello
        for ((i = 0; i < 1000; i++)); do
            n=$(ckpt_u32 "$WORK/p2_#.png.ckpt" 96)
            [ -n "$n" ] && [ "$n" -ge 1 ] 2>/dev/null && break
            kill -0 $pid 2>/dev/null || break
            sleep 0.01
        done
        [ -n "$victim" ] && kill -STOP "$victim"
        for ((i = 0; i < 600; i++)); do
            two_partial "$WORK/p2_#.png.ckpt" >/dev/null && break
            kill -0 $pid 2>/dev/null || break
            sleep 0.02
        done
        kill -USR1 $pid 2>/dev/null
        [ -n "$victim" ] && kill -CONT "$victim" 2>/dev/null
        wait $pid
        got=$(two_partial "$WORK/p2_#.png.ckpt")
    done
    [ -n "$got" ] && pass "two in flight: the stop's checkpoint holds frames $got, both partial" ||
        fail "two in flight: no checkpoint with two partial frames in 5 runs"
    if [ -n "$got" ]; then
        "$BIN" "${P[@]}" -j 2 --frames 0-5 -o "$WORK/p2_#.png" --resume --stats "$WORK/p2_#.json" >/dev/null 2>"$WORK/p2.err"
        check_eq "two in flight: resume exit status" $? 0
        continued=0
        for f in $got; do
            segs=$(stat_of "$WORK/p2_$f.json" ray_segments) all=$(stat_of "$WORK/pref_$f.json" ray_segments)
            [ -n "$segs" ] && [ -n "$all" ] && [ "$segs" -lt "$all" ] && continued=$((continued + 1))
        done
        check_eq "two in flight: both frames continued from the checkpoint" "$continued" "2"
        same=0
        for f in 0 1 2 3 4 5; do cmp -s "$WORK/p2_$f.png" "$WORK/pref_$f.png" && same=$((same + 1)); done
        check_eq "two in flight: resumed frames identical" "$same of 6" "6 of 6"
    fi
fi
# another job's checkpoint (another range) is refused
"$BIN" "${F[@]}" --frames 0-3 -o "$WORK/fo_#.png" -s 2 --keep-checkpoint >/dev/null 2>&1
mv "$WORK/fo_#.png.ckpt" "$WORK/keep.ckpt"
rm -f "$WORK"/fo_*.png
mv "$WORK/keep.ckpt" "$WORK/fo_#.png.ckpt"
expect_refusal 3 "frame job: checkpoint of another range" "different job (last frame 3, this job has 4)" \
    "$BIN" "${F[@]}" -s 2 --frames 0-4 -o "$WORK/fo_#.png" --resume
expect_refusal 3 "frame job: checkpoint of another turntable" "different job (turntable frames 4, this job has 8)" \
    "$BIN" "${F[@]}" --frames 0-3 -s 2 --turntable 60:8 -o "$WORK/fo_#.png" --resume

# Refusals: exit 3, one clear line, nothing rendered.
B=(--width 160 --height 96 -s 300 -q -o "$WORK/x.png")
"$BIN" "${B[@]}" --keep-checkpoint -s 2 >/dev/null 2>&1
[ -s "$WORK/x.png.ckpt" ] && pass "--keep-checkpoint keeps it" || fail "--keep-checkpoint: no checkpoint"
expect_refusal 3 "checkpoint of another job (samples)" "different job (samples 2" "$BIN" "${B[@]}" -s 3 --resume
expect_refusal 3 "checkpoint of another job (seed)" "different job (seed" "$BIN" "${B[@]}" -s 2 --seed 5 --resume
expect_refusal 3 "existing checkpoint without --resume" "pass --resume" "$BIN" "${B[@]}" -s 2
# Samples of another sampler, or without the roulette, are not mixed in.
expect_refusal 3 "checkpoint of another sampler" "different job (sampler 1" "$BIN" "${B[@]}" -s 2 --sampler random --resume
expect_refusal 3 "checkpoint with the roulette" "different job (roulette 1" "$BIN" "${B[@]}" -s 2 --no-roulette --resume
# The rest of the job's identity, one field at a time (test_checkpoint
# covers the intersector, which only a build with Embree can change here).
expect_refusal 3 "checkpoint of another width" "different job (width 160, this job has 161)" \
    "$BIN" "${B[@]}" -s 2 --width 161 --resume
expect_refusal 3 "checkpoint of another height" "different job (height 96, this job has 95)" \
    "$BIN" "${B[@]}" -s 2 --height 95 --resume
expect_refusal 3 "checkpoint of another max depth" "different job (max depth 50, this job has 5)" \
    "$BIN" "${B[@]}" -s 2 --max-depth 5 --resume
expect_refusal 3 "checkpoint of another diffuse model" "different job (diffuse model 0, this job has 1)" \
    "$BIN" "${B[@]}" -s 2 --diffuse sphere --resume
expect_refusal 3 "checkpoint of another scene" "different job (scene " "$BIN" "${B[@]}" -s 2 --grid 5 --resume
cp "$WORK/x.png.ckpt" "$WORK/y.ckpt"
printf '\x01' | dd of="$WORK/x.png.ckpt" bs=1 seek=200 conv=notrunc 2>/dev/null
expect_refusal 3 "corrupt checkpoint" "corrupt or truncated" "$BIN" "${B[@]}" -s 2 --resume
head -c 100 "$WORK/y.ckpt" >"$WORK/x.png.ckpt"
expect_refusal 3 "truncated checkpoint" "corrupt or truncated" "$BIN" "${B[@]}" -s 2 --resume
rm -f "$WORK/x.png.ckpt"
expect_refusal 3 "resume without a checkpoint" "no checkpoint" "$BIN" "${B[@]}" -s 2 --resume

# Full disk (needs a tmpfs mount: root in a sandbox that allows it).
mkdir -p "$WORK/full"
if mount -t tmpfs -o size=48k tmpfs "$WORK/full" 2>/dev/null; then
    printf precious >"$WORK/full/x.png"
    "$BIN" --width 300 --height 200 -s 1 -q -o "$WORK/full/x.png" >/dev/null 2>"$WORK/e.txt"
    st=$?
    [ $st -eq 1 ] && grep -q "no space left" "$WORK/e.txt" && pass "full disk -> $(cat "$WORK/e.txt")" ||
        fail "full disk: status $st: $(cat "$WORK/e.txt")"
    [ "$(ls "$WORK/full")" = x.png ] && pass "full disk: no partial file" || fail "full disk left: $(ls "$WORK/full")"
    check_eq "full disk: the existing output is untouched" "$(cat "$WORK/full/x.png")" precious
    rm -f "$WORK/full/x.png"
    # With the checkpoint elsewhere, the finished render survives the full
    # disk and a resume only writes the image.
    "$BIN" --width 300 --height 200 -s 2 -q -o "$WORK/full/y.png" --checkpoint "$WORK/fulldisk.ckpt" >/dev/null 2>"$WORK/e.txt"
    grep -q "saved in the checkpoint" "$WORK/e.txt" && [ -s "$WORK/fulldisk.ckpt" ] && pass "full disk: render kept in the checkpoint" ||
        fail "full disk: checkpoint not kept: $(cat "$WORK/e.txt")"
    "$BIN" --width 300 --height 200 -s 2 -q -o "$WORK/y.png" --checkpoint "$WORK/fulldisk.ckpt" --resume \
        --stats "$WORK/y.json" >"$WORK/y.out" 2>&1
    "$BIN" --width 300 --height 200 -s 2 -q -o "$WORK/y-direct.png" >/dev/null 2>&1
    grep -q "100.0% of the samples restored" "$WORK/y.out" && cmp -s "$WORK/y.png" "$WORK/y-direct.png" &&
        pass "full disk: resume writes the identical image" || fail "full disk: resume: $(head -c 300 "$WORK/y.out")"
    check_eq "full disk: the resume renders no unit and no ray segment" \
        "$(stat_of "$WORK/y.json" units) $(stat_of "$WORK/y.json" ray_segments)" "0 0"
    umount "$WORK/full"
else
    skip "full-disk cases need permission to mount a tmpfs"
fi

# Progressive previews: written during the run, each a valid PNG.
"$BIN" --width 64 --height 40 -s 8 --passes 4 -j 2 -o "$WORK/prog.png" --preview "$WORK/prev.png" >/dev/null 2>&1
check_eq "progressive run exit status" $? 0
[ -s "$WORK/prev.png" ] && pass "preview written" || fail "no preview file"
"$BIN" --width 64 --height 40 -s 8 -j 2 -o "$WORK/flat.png" >/dev/null 2>&1
cmp -s "$WORK/prog.png" "$WORK/flat.png" && pass "progressive final = one-pass image" || fail "progressive image differs"
cmp -s "$WORK/prev.png" "$WORK/flat.png" && fail "last preview is the final image (should be pass 3 of 4)" || pass "preview is an earlier pass"

# Trace and stats are valid JSON with one event per unit.
"$BIN" --width 64 --height 40 -s 4 -q -o "$WORK/t.png" --trace "$WORK/t.json" --stats "$WORK/s.json" >"$WORK/t.out"
units=$(sed -n 's/^ranks:.* \([0-9]*\) units.*/\1/p' "$WORK/t.out")
got=$(python3 -c "import json,sys; t=json.load(open('$WORK/t.json')); print(sum(1 for e in t['traceEvents'] if e.get('ph')=='X'))")
check_eq "trace has one event per unit" "$got" "$units"
hash=$(python3 -c "import json; print(json.load(open('$WORK/s.json'))['image_hash'])")
check_eq "stats image hash" "$hash" "$(sed -n 's/^image hash: *//p' "$WORK/t.out")"
finish
