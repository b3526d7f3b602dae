#!/bin/bash
# ab_error.sh [REV] [--rounds N] [--ref-spp S] [--texture-dir DIR] [--cases "SCENE:SIZE:SPP ..."]
# Decide a change to the sampling (the images change, so tools/ab_render.sh's
# rate alone says nothing): the working tree's program (A) against the one
# built from git revision REV (B, default HEAD), release builds without MPI,
# at the same samples on each case. For each scene and size a reference is
# rendered once by A at --ref-spp (default 2048) on every core; each case's
# renders alternate A, B, A, B... (--rounds pairs, default 5) on one core
# (-j 1) so that a drift in the machine's speed hits both; the images, so
# the errors, are the same every round. Prints each side's display-space
# RMSE (gamma 2, 0-255, per pixel: tools/compare_images.py --block 1)
# against the reference, its least CPU seconds (user + system, the whole
# process; this VM's noise only ever slows a run, by up to 1.5x, so the
# least is steadier than the median), and B's MSE x seconds over A's: how
# many times less time A takes to the same error, since the MSE of an
# unbiased render falls as one over its samples. Default cases: the lit
# scenes at 128 x 128, 64 spp, and book3-final at 256 x 256 at 8 and 32
# spp (8: the error of the book's own program at 64 spp, PERFORMANCE.md).
# book2-final and earth read earthmap.jpg from --texture-dir (default: the
# current directory).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$ROOT/tools/bench_lib.sh"
DIR=${AB_ERROR_DIR:-$ROOT/build-ab-error}
REV=HEAD ROUNDS=5 REF=2048 TEX=.
CASES="cornell-box:128:64 book2-final:128:64 cornell-smoke:128:64 simple-light:128:64 book3-final:256:8 book3-final:256:32"
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then
    REV=$1
    shift
fi
while [ $# -gt 0 ]; do
    case $1 in
    --rounds) ROUNDS=${2:?--rounds needs a number}; shift ;;
    --ref-spp) REF=${2:?--ref-spp needs a number}; shift ;;
    --texture-dir) TEX=${2:?--texture-dir needs a directory}; shift ;;
    --cases) CASES=${2:?--cases needs a list}; shift ;;
    *) echo "ab_error.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
[[ $ROUNDS =~ ^[1-9][0-9]*$ ]] || { echo "ab_error.sh: --rounds must be a positive number" >&2; exit 2; }
build_a_b ab_error.sh "$ROOT" "$REV" "$DIR" -DRT_MPI=OFF -DBUILD_TESTING=OFF
COMMIT=$(cat "$DIR/b.commit")

# render SIDE OUT SCENE SIZE SPP THREADS: prints "cpu" (seconds, user + system).
render() {
    local t
    t=$( { TIMEFORMAT='%U %S'; time "$DIR/$1/rt-mpi" --scene "$3" --width "$4" --height "$4" -s "$5" -j "$6" \
        --texture-dir "$TEX" --no-checkpoint -q -o "$2" >/dev/null 2>"$DIR/err"; } 2>&1) ||
        { echo "ab_error.sh: the render of $1 ($3) failed: $(head -c 300 "$DIR/err")" >&2; exit 1; }
    awk '{printf "%.3f", $1 + $2}' <<<"$t"
}

echo "ab_error.sh: A = working tree, B = $REV (${COMMIT:0:7}); reference: A at $REF spp; $ROUNDS alternating" \
    "rounds, -j 1, least CPU seconds; RMSE: display space (gamma 2, 0-255)"
printf '%-14s %8s %6s | %8s %8s | %8s %8s | %s\n' scene size spp "A RMSE" "A s" "B RMSE" "B s" \
    "A's speed to equal error (B MSE x s / A MSE x s)"
for c in $CASES; do
    IFS=: read -r scene size spp <<<"$c"
    ref=$DIR/ref-$scene-$size.png
    key="$(cksum <"$DIR/a/rt-mpi") $REF" # rendered again when A's program or --ref-spp changes
    [ -s "$ref" ] && [ "$(cat "$ref.key" 2>/dev/null)" = "$key" ] ||
        { render a "$ref" "$scene" "$size" "$REF" "$(nproc)" >/dev/null && echo "$key" >"$ref.key"; }
    : >"$DIR/t.a" && : >"$DIR/t.b"
    for ((r = 0; r < ROUNDS; r++)); do
        for s in a b; do
            render $s "$DIR/$s.png" "$scene" "$size" "$spp" 1 >>"$DIR/t.$s"
            echo >>"$DIR/t.$s"
        done
    done
    ta=$(sort -g "$DIR/t.a" | grep . | head -1) tb=$(sort -g "$DIR/t.b" | grep . | head -1)
    ea=$(display_rmse "$ref" "$DIR/a.png") eb=$(display_rmse "$ref" "$DIR/b.png")
    printf '%-14s %8s %6s | %8s %8s | %8s %8s | %s\n' "$scene" "$size" "$spp" "$ea" "$ta" "$eb" "$tb" \
        "$(awk -v ea="$ea" -v eb="$eb" -v ta="$ta" -v tb="$tb" 'BEGIN {printf "%.2fx", eb * eb * tb / (ea * ea * ta)}')"
done
