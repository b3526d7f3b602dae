#!/bin/bash
# e2e_frames.sh BIN PNGINFO MPIRUN
# Frame jobs (--frames, --frame, --turntable): bad input refused with one
# line, exit 2 and nothing written; every frame of a range byte-identical to
# that frame rendered alone (--frame N), for any -np, -j, --band and
# --split; each file names its frame.
BIN=$1 PNGINFO=$2 MPIRUN=${3:-}
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
else
    skip "mpirun not found: frame jobs over ranks"
fi
# ---- rank 0's writer thread ---------------------------------------------------
# 8 frames over 2 ranks: each file (written by the writer thread while the
# next frame renders) is the frame alone, the summaries come in frame order,
# and each names the peak of frames held on rank 0 (1 to 4: at most 2 waiting,
# one being written, one rendering), never falling.
W=(--width 40 --height 24 -s 2 --grid 2 --turntable 45:8 -q)
for f in 0 1 2 3 4 5 6 7; do alone writer "$f" "${W[@]}"; done
if [ -n "$MPIRUN" ]; then
    same_frames "writer thread: 8 frames -np 2" writer 0 7 1 mpirun_np 2 "$BIN" "${W[@]}" -j 1 --frames 0-7
else
    same_frames "writer thread: 8 frames -j 2" writer 0 7 1 "$BIN" "${W[@]}" -j 2 --frames 0-7
fi
check_eq "writer thread: summaries in frame order" "$(sed -n 's/^frame: *//p' "$WORK/seq.out" | tr '\n' ' ')" \
    "0 1 2 3 4 5 6 7 "
peaks=$(sed -n 's/^frames held: *peak \([0-9]*\) on rank 0 (at most 2 waiting for the writer thread)$/\1/p' "$WORK/seq.out" | tr '\n' ' ')
check_eq "writer thread: every summary names the peak (1 to 4, never falling)" \
    "$(awk -v p="$peaks" 'BEGIN { n = split(p, a, " "); ok = n == 8; for (i = 1; i <= n; i++) ok = ok && a[i] >= 1 && a[i] <= 4 && (i == 1 || a[i] >= a[i-1]); print ok ? "yes" : "no: " p }')" "yes"
# a write that fails in the middle of the range (frame 3's name is a
# directory): one line, exit 1; the frames before it written, none after
rm -rf "$WORK/wf" && mkdir -p "$WORK/wf/f_3.png"
"$BIN" "${W[@]}" -j 2 --frames 0-7 -o "$WORK/wf/f_#.png" >/dev/null 2>"$WORK/wf.err"
check_eq "writer thread: a failed write's exit status" "$?" "1"
check_eq "writer thread: a failed write's one line" "$(cat "$WORK/wf.err")" \
    "rt-mpi: error: writing $WORK/wf/f_3.png: $(sed -n 's/^rt-mpi: error: writing [^:]*: //p' "$WORK/wf.err")"
check_eq "writer thread: a failed write's files" "$(ls "$WORK/wf" | tr '\n' ' ')" "f_0.png f_1.png f_2.png f_3.png "
check_eq "writer thread: nothing written into the directory" "$(ls -A "$WORK/wf/f_3.png" | wc -l)" "0"
finish
