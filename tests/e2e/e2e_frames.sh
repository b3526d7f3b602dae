#!/bin/bash
# e2e_frames.sh BIN PNGINFO MPIRUN HOOKS_BIN
# Frame jobs (--frames, --frame, --turntable): bad input refused with one
# line, exit 2 and nothing written; every frame of a range byte-identical to
# that frame rendered alone (--frame N), for any -np, -j, --band and
# --split; each file names its frame; rank 0's render thread waits at the
# cap on frames in flight without polling.
BIN=$1 PNGINFO=$2 MPIRUN=${3:-} HOOKS_BIN=${4:-}
source "$(dirname "$0")/../support/lib.sh"
O="$WORK/out"

# ---- bad input ---------------------------------------------------------------
bad() { # label pattern args...
    local label=$1 pattern=$2
    shift 2
    expect_refusal 2 "$label" "$pattern" "$BIN" --width 32 --height 16 -s 2 -q "$@"
}
bad "reversed range" "reversed" --frames 5-2 -o "$O/f_#.png"
bad "range not a range" "not a frame range" --frames 1-x -o "$O/f_#.png"
bad "step 0" "a step of 0" --frames 1-4:0 -o "$O/f_#.png"
bad "frame past the last" "not a frame range" --frames 0-1000000000 -o "$O/f_#.png"
bad "--frame with a range" "not a frame number" --frame 1-3 -o "$O/f_#.png"
bad "--frames and --frame" "one of --frames and --frame" --frames 1-3 --frame 2 -o "$O/f_#.png"
bad "--turntable without frames" "give the frames" --turntable 90:4 -o "$O/f_#.png"
bad "--turntable without FRAMES" "DEGREES:FRAMES" --frames 0-2 --turntable 90 -o "$O/f_#.png"
bad "--turntable every 0 frames" "DEGREES:FRAMES" --frames 0-2 --turntable 90:0 -o "$O/f_#.png"
bad "--turntable not a number" "DEGREES:FRAMES" --frames 0-2 --turntable abc:4 -o "$O/f_#.png"
bad "patterns that collide" "would be '.*f_0.png'" --frames 0-3 -o "$O/f_#.png" --stats "$O/f_#.png"
bad "pattern and done file collide" "would be" --frames 0-3 -o "$O/f_#.png" --done-file "$O/f_2.png"
bad "pattern in a missing directory" "does not exist" --frames 0-2 -o "$O/nodir/f_#.png"
bad "'#' in the directory" "not the directory" --frames 0-2 -o "$O/d#/f.png"
bad "progressive passes in a range" "not a frame range" --frames 0-2 --passes 2 -o "$O/f_#.png"

# ---- every frame of a range is the frame alone ------------------------------
# one job for each case below; its frames against --frame N alone (-j 1)
declare -A HASHES
alone() { # tag frame args...
    local tag=$1 n=$2
    shift 2
    "$BIN" "$@" -j 1 --frame "$n" -o "$WORK/alone_${tag}_#.png" >/dev/null 2>"$WORK/alone.err" ||
        fail "$tag: --frame $n alone: $(head -c 300 "$WORK/alone.err")"
}
same_frames() { # label tag first last step -- launcher... -- args...
    local label=$1 tag=$2 a=$3 b=$4 step=$5 f out
    shift 5
    rm -rf "$WORK/seq" && mkdir -p "$WORK/seq"
    if ! "$@" -o "$WORK/seq/f_###.png" >"$WORK/seq.out" 2>"$WORK/seq.err"; then
        fail "$label: exit status $? ($(head -c 300 "$WORK/seq.err"))"
        return
    fi
    local n=0 same=0
    for ((f = a; f <= b; f += step)); do
        n=$((n + 1))
        out=$(printf "%s/seq/f_%03d.png" "$WORK" "$f")
        cmp -s "$out" "$(printf "%s/alone_%s_%d.png" "$WORK" "$tag" "$f")" && same=$((same + 1))
    done
    check_eq "$label: frames identical to --frame N alone" "$same of $n" "$n of $n"
    check_eq "$label: no other file" "$(ls "$WORK/seq" | wc -l)" "$n"
}

# book 1's final scene on a turntable (a quarter turn every 4 frames)
T=(--width 48 --height 32 -s 4 --grid 3 --turntable 90:4 -q)
for f in 1 3 5; do alone turn "$f" "${T[@]}"; done
"$PNGINFO" --text "$WORK/alone_turn_3.png" >"$WORK/text"
check_eq "the PNG names its frame" "$(sed -n 's/^rt-mpi:frame=//p' "$WORK/text")" "3"
read -r -a cmd <<<"$(sed -n 's/^rt-mpi:command=rt-mpi //p' "$WORK/text")"
"$BIN" "${cmd[@]}" -q -o "$WORK/again_#.png" >/dev/null
cmp -s "$WORK/again_3.png" "$WORK/alone_turn_3.png" && pass "the frame's own command renders it again" ||
    fail "the frame's command (${cmd[*]}) gives another image"
cmp -s "$WORK/alone_turn_1.png" "$WORK/alone_turn_3.png" && fail "frames 1 and 3 of the turntable are the same" ||
    pass "frames 1 and 3 of the turntable differ"
same_frames "turntable -j 2" turn 1 5 2 "$BIN" "${T[@]}" -j 2 --frames 1-5:2
same_frames "turntable --band 1 -j 2" turn 1 5 2 "$BIN" "${T[@]}" -j 2 --band 1 --frames 1-6:2
# book 2's moving spheres: each frame its own interval of the rays' time
B=(--scene bouncing-spheres --width 40 --height 24 -s 4 --max-depth 8 -q)
for f in 0 1 2; do alone bounce "$f" "${B[@]}"; done
cmp -s "$WORK/alone_bounce_0.png" "$WORK/alone_bounce_1.png" && fail "frames 0 and 1 of the moving spheres are the same" ||
    pass "frames 0 and 1 of the moving spheres differ"
same_frames "moving spheres -j 1" bounce 0 2 1 "$BIN" "${B[@]}" -j 1 --frames 0-2
# the progress line counts the rows of the whole range (its last, of frame 3 of 3)
"$BIN" --scene bouncing-spheres --width 40 --height 24 -s 4 --max-depth 8 -j 2 --frames 0-2 -o "$WORK/seq/p_#.png" >/dev/null 2>"$WORK/seq.err"
check_eq "progress over the whole range: last line" "$(grep -o 'frame [0-9/]* rows [0-9/]* ([0-9.]*%)' "$WORK/seq.err" | tail -1)" \
    "frame 3/3 rows 72/72 (100.0%)"
if [ -n "$MPIRUN" ]; then
    same_frames "turntable -np 1" turn 1 5 2 mpirun_np 1 "$BIN" "${T[@]}" -j 2 --frames 1-5:2
    same_frames "turntable -np 2 --band 3" turn 1 5 2 mpirun_np 2 "$BIN" "${T[@]}" -j 1 --band 3 --frames 1-5:2
    same_frames "turntable -np 3 --split samples" turn 1 5 2 mpirun_np 3 "$BIN" "${T[@]}" -j 1 --split samples --frames 1-5:2
    same_frames "moving spheres -np 2 -j 2" bounce 0 2 1 mpirun_np 2 "$BIN" "${B[@]}" -j 2 --frames 0-2
    same_frames "moving spheres -np 3 --split columns" bounce 0 2 1 mpirun_np 3 "$BIN" "${B[@]}" -j 1 --split columns --frames 0-2
    # Units across frames (one schedule for the range): each frame's
    # --stats gives, on rank 0's clock, when its first unit was handed out
    # (render_start_seconds) and for how long until its last sums were in
    # (render_seconds); some frame k+1 must start before frame k ends (with
    # frames one after another none does). Its trace (global rows y0 =
    # frame index x height + row) holds its own frame's units only, none
    # across a frame's end.
    rm -rf "$WORK/tr" && mkdir -p "$WORK/tr"
    mpirun_np 3 "$BIN" --width 64 --height 32 -s 32 --grid 3 --turntable 90:4 -q -j 1 --frames 0-5 \
        -o "$WORK/tr/f_#.png" --trace "$WORK/tr/t_#.json" --stats "$WORK/tr/s_#.json" >/dev/null 2>"$WORK/tr.err" ||
        fail "units across frames: the job failed: $(head -c 300 "$WORK/tr.err")"
    overlap=$(python3 - "$WORK/tr" 32 6 <<'PY'
import json, sys
d, h, n = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
wrong, start, end = 0, {}, {}
for f in range(n):
    for e in json.load(open("%s/t_%d.json" % (d, f)))["traceEvents"]:
        if e.get("ph") == "X":
            k = e["args"]["y0"] // h
            wrong += k != f or (e["args"]["y1"] - 1) // h != k  # its own frame's, never across
    s = json.load(open("%s/s_%d.json" % (d, f)))
    start[f] = s["render_start_seconds"]
    end[f] = start[f] + s["render_seconds"]
print("wrong" if wrong else sum(1 for k in range(n - 1) if start[k + 1] < end[k]))
PY
)
    [ -n "$overlap" ] && [ "$overlap" != wrong ] && [ "$overlap" -gt 0 ] &&
        pass "units across frames: $overlap of 5 frames start before the one before them ends" ||
        fail "units across frames: no frame starts before the one before it ends ($overlap)"
    # Rank 0's render thread at the cap: rank 1 sleeps 200 ms after each
    # unit (a test hook), so the first frames' units in its hands keep the
    # cap shut while ranks 0 and 2 have rendered every unit that is ready.
    # Rank 0's render thread then waits until a frame is released (12 in
    # all) instead of napping and asking again: at most 2 waits a frame
    # (one more when a worker took the unit first), where a 0.2 ms poll
    # comes back hundreds of times; and at least one, or the cap never
    # bound and this shows nothing.
    if [ -n "$HOOKS_BIN" ]; then
        rm -rf "$WORK/cap" && mkdir -p "$WORK/cap"
        RT_TEST_SLOW_RANK=1:200 mpirun_np 3 "$HOOKS_BIN" --width 64 --height 16 -s 64 --grid 3 --turntable 90:4 \
            -j 2 --frames 0-11 -o "$WORK/cap/f_#.png" >"$WORK/cap.out" 2>"$WORK/cap.err" ||
            fail "rank 0 at the cap: the job failed: $(head -c 300 "$WORK/cap.err")"
        waits=$(sed -n 's/^rank 0 waited: *\([0-9]*\) times for units .*/\1/p' "$WORK/cap.out")
        check_eq "rank 0 at the cap: its render thread waited ${waits:-no} times (1 to 24: no polling)" \
            "$([ -n "$waits" ] && [ "$waits" -ge 1 ] && [ "$waits" -le 24 ] && echo yes || echo no)" "yes"
    else
        skip "no test-hooks build: rank 0 at the cap"
    fi
else
    skip "mpirun not found: frame jobs over ranks"
fi
# ---- rank 0's writer thread ---------------------------------------------------
# 8 frames over 2 ranks: each file (written by the writer thread while
# later frames render) is the frame alone, each frame has one summary (in
# the order the frames completed), and each names the peak of frames held on
# rank 0 (1 to 7: at most 4 in flight, 2 waiting, one being written), never
# falling; the range's summary closes the output with its peak.
W=(--width 40 --height 24 -s 2 --grid 2 --turntable 45:8 -q)
for f in 0 1 2 3 4 5 6 7; do alone writer "$f" "${W[@]}"; done
if [ -n "$MPIRUN" ]; then
    same_frames "writer thread: 8 frames -np 2" writer 0 7 1 mpirun_np 2 "$BIN" "${W[@]}" -j 1 --frames 0-7
else
    same_frames "writer thread: 8 frames -j 2" writer 0 7 1 "$BIN" "${W[@]}" -j 2 --frames 0-7
fi
check_eq "writer thread: one summary a frame" "$(sed -n 's/^frame: *//p' "$WORK/seq.out" | sort -n | tr '\n' ' ')" \
    "0 1 2 3 4 5 6 7 "
held='(at most 4 in flight, 2 waiting for the writer thread, 1 being written)'
peaks=$(sed -n "s/^frames held: *peak \([0-9]*\) on rank 0 $held\$/\1/p" "$WORK/seq.out" | tr '\n' ' ')
check_eq "writer thread: every summary names the peak (1 to 7, never falling)" \
    "$(awk -v p="$peaks" 'BEGIN { n = split(p, a, " "); ok = n == 8; for (i = 1; i <= n; i++) ok = ok && a[i] >= 1 && a[i] <= 7 && (i == 1 || a[i] >= a[i-1]); print ok ? "yes" : "no: " p }')" "yes"
check_eq "writer thread: the range's summary ends the output" \
    "$(tail -1 "$WORK/seq.out" | sed -n "s/^frames held: *peak [1-7] on rank 0 over the range $held\$/ok/p")" "ok"
# a write that fails in the middle of the range (frame 3's name is a
# directory): one line, exit 1; the frames handed to the writer before it
# are written (frames complete in any order: which ones varies), each
# complete and the frame alone, and no temporary file is left
rm -rf "$WORK/wf" && mkdir -p "$WORK/wf/f_3.png"
"$BIN" "${W[@]}" -j 2 --frames 0-7 -o "$WORK/wf/f_#.png" >/dev/null 2>"$WORK/wf.err"
check_eq "writer thread: a failed write's exit status" "$?" "1"
check_eq "writer thread: a failed write's one line" "$(cat "$WORK/wf.err")" \
    "rt-mpi: error: writing $WORK/wf/f_3.png: $(sed -n 's/^rt-mpi: error: writing [^:]*: //p' "$WORK/wf.err")"
bad_files=0
for f in $(ls -A "$WORK/wf"); do
    n=$(echo "$f" | sed -n 's/^f_\([0-9]\)\.png$/\1/p')
    [ "$f" = f_3.png ] && continue
    [ -n "$n" ] && cmp -s "$WORK/wf/$f" "$WORK/alone_writer_$n.png" || bad_files=$((bad_files + 1))
done
check_eq "writer thread: a failed write leaves only whole frames (and no temp file)" "$bad_files" "0"
check_eq "writer thread: nothing written into the directory" "$(ls -A "$WORK/wf/f_3.png" | wc -l)" "0"
finish
