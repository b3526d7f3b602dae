#!/bin/bash
# e2e_bad_input.sh BIN MPIRUN
# Every class of bad input: one line "rt-mpi: error: ...", exit status 2,
# no output file created. (That a failed write leaves an existing file
# untouched is checked with a full disk in e2e_resume.sh.)
BIN=$1 MPIRUN=${2:-}
source "$(dirname "$0")/../support/lib.sh"
OUT="$WORK/out/out.png" # expect_refusal checks that $WORK/out stays empty
mkdir -p "$WORK/ro" "$WORK/adir.png"
chmod 555 "$WORK/ro"

expect_error() { # label pattern args...
    local label=$1 pattern=$2
    shift 2
    expect_refusal 2 "$label" "$pattern" "$BIN" --width 32 --height 16 -s 2 -q "$@"
}
expect_error "non-number width" "not a whole number" --width abc -o "$OUT"
expect_error "trailing junk" "not a whole number" -s 10x -o "$OUT"
expect_error "negative samples" "not a whole number" -s -5 -o "$OUT"
expect_error "zero samples" "out of range" -s 0 -o "$OUT"
expect_error "zero width" "out of range" --width 0 -o "$OUT"
expect_error "zero height" "out of range" --height 0 -o "$OUT"
expect_error "zero depth" "out of range" --max-depth 0 -o "$OUT"
expect_error "huge samples" "out of range" -s 99999999999999999999999 -o "$OUT"
expect_error "huge width" "out of range" --width 4294967297 -o "$OUT"
expect_error "too many pixels" "too large" --width 1000000 --height 1000000 -o "$OUT"
# The largest image allowed (2^32 pixels) needs ~108 GiB on rank 0, ~476
# GiB with adaptive sampling and both denoiser buffers (13 sums a pixel).
if [ "$(awk '/MemTotal/ {print $2}' /proc/meminfo)" -lt 100000000 ]; then
    expect_error "memory beyond the machine" "GiB of memory" --width 65536 --height 65536 -o "$OUT"
elif [ "$(awk '/MemTotal/ {print $2}' /proc/meminfo)" -lt 450000000 ]; then
    expect_error "memory beyond the machine (wide layout)" "GiB of memory" --width 65536 --height 65536 \
        --noise-threshold 0.05 --aov albedo,normal -o "$OUT"
else
    skip "memory case (this machine has more than 450 GB: no image size is too big for it)"
fi
expect_error "negative threads" "not a whole number" -j -1 -o "$OUT"
expect_error "absurd threads" "out of range" -j 100000 -o "$OUT"
expect_error "unknown option" "unknown option '--bogus'" --bogus -o "$OUT"
expect_error "unknown sampler" "--sampler: 'halton' is not one of sobol, random" --sampler halton -o "$OUT"
expect_error "roulette both ways" "--roulette and --no-roulette" --roulette --no-roulette -o "$OUT"
expect_error "missing value" "needs a value" -o "$OUT" --width
# A word that is no option is the scene file: one at most, and it must be there.
expect_error "second scene file" "unexpected argument 'b.json': one scene file only" -o "$OUT" a.json b.json
expect_error "missing scene file" "nowhere.json" -o "$OUT" "$WORK/nowhere.json"
expect_error "missing directory" "directory does not exist" -o "$WORK/nodir/x.png"
expect_error "unsupported extension" "unsupported file type '.jpg'" -o "$WORK/x.jpg"
expect_error "output is a directory" "is a directory" -o "$WORK/adir.png"
if [ "$(id -u)" -ne 0 ]; then
    expect_error "read-only directory" "directory is not writable" -o "$WORK/ro/x.png"
elif mkdir -p "$WORK/rofs" && mount -t tmpfs -o ro,size=64k tmpfs "$WORK/rofs" 2>/dev/null; then
    # root may write into any directory: a read-only file system stops it
    expect_error "read-only file system" "directory is not writable" -o "$WORK/rofs/x.png"
    umount "$WORK/rofs"
else
    skip "read-only directory case (root, and no permission to mount a tmpfs)"
fi
expect_error "bad accel" "not one of" --accel magic -o "$OUT"
expect_error "--preview without --passes" "only with --passes 2 or more" --preview "$WORK/out/p.png" -o "$OUT"
OMP_NUM_THREADS=abc "$BIN" --width 32 --height 16 -s 2 -q -o "$OUT" >/dev/null 2>"$WORK/e.txt"
check_eq "OMP_NUM_THREADS=abc exit status" $? 2
grep -q "^rt-mpi: error: OMP_NUM_THREADS='abc'" "$WORK/e.txt" && pass "OMP_NUM_THREADS message" || fail "OMP_NUM_THREADS message: $(cat "$WORK/e.txt")"
# More threads than cores: a warning, and the render still completes.
"$BIN" --width 32 --height 16 -s 2 -q -j 64 -o "$WORK/many.png" --no-checkpoint >/dev/null 2>"$WORK/e.txt"
check_eq "-j 64 on a small machine: exit status" $? 0
grep -q "^rt-mpi: warning: -j 64 is more than" "$WORK/e.txt" && pass "-j 64 warns" || fail "-j 64: $(cat "$WORK/e.txt")"
if [ -n "$MPIRUN" ]; then
    mpirun_np 2 "$BIN" --width abc -o "$OUT" >"$WORK/o.txt" 2>"$WORK/e.txt"
    status=$?
    n=$(grep -c "rt-mpi: error:" "$WORK/e.txt")
    [ $status -eq 2 ] && [ "$n" -eq 1 ] && pass "under mpirun -np 2: status 2, one message" ||
        fail "under mpirun: status $status, $n messages: $(head -c 300 "$WORK/e.txt")"
    # A setting only one node has wrong (here rank 1's RT_ACCEL) stops the
    # job with that rank's own line, before anything renders.
    mpirun_np 2 sh -c '[ "$OMPI_COMM_WORLD_RANK" = 1 ] && export RT_ACCEL=bogus; exec "$0" "$@"' \
        "$BIN" --width 32 -s 2 -o "$WORK/acc.png" --no-checkpoint >"$WORK/o.txt" 2>"$WORK/e.txt"
    status=$?
    [ $status -eq 2 ] && grep -q "^rt-mpi: error: rank 1: RT_ACCEL='bogus'" "$WORK/e.txt" && [ ! -e "$WORK/acc.png" ] &&
        pass "one rank's bad RT_ACCEL: status 2, its own message" ||
        fail "one rank's bad RT_ACCEL: status $status: $(grep -m2 rt-mpi "$WORK/e.txt")"
else
    skip "mpirun cases: no mpirun"
fi
chmod 755 "$WORK/ro"
finish
