#!/bin/bash
# ab_render.sh [REV] [--rounds N] [rt-mpi options...]
# Decide a change to the render core by timing whole renders: the working
# tree's program (A) against the one built from git revision REV (B, default
# HEAD), both release builds as users run them (LTO, which inlines the
# intersector into the path loop: tools/ab_bvh.sh times it as a function of
# its own, and a gain there need not survive this), without MPI, one thread.
# The renders alternate A, B, A, B... (--rounds pairs, default 5) so a drift
# in the machine's speed hits both; prints the median ray segments/s of each,
# A / B, and whether the two images are identical (image hash).
# Default render: final scene, 600x400, 16 spp, -j 1; options given here are
# added after those, so they win (e.g. --width 300 -s 4 --accel brute).
# Builds are kept in $AB_RENDER_DIR (default build-ab-render/).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$ROOT/tools/bench_lib.sh"
DIR=${AB_RENDER_DIR:-$ROOT/build-ab-render}
REV=HEAD
ROUNDS=5
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then
    REV=$1
    shift
fi
if [ "${1:-}" = --rounds ]; then
    ROUNDS=${2:?--rounds needs a number}
    shift 2
fi
[[ $ROUNDS =~ ^[1-9][0-9]*$ ]] || { echo "ab_render.sh: --rounds must be a positive number" >&2; exit 2; }
build_a_b ab_render.sh "$ROOT" "$REV" "$DIR" -DRT_MPI=OFF -DBUILD_TESTING=OFF
COMMIT=$(cat "$DIR/b.commit")
OPTS=(--width 600 --height 400 -s 16 -j 1 "$@")
run() { # run a|b: appends the rate to $DIR/rates.X, the image hash to $DIR/hash.X
    "$DIR/$1/rt-mpi" "${OPTS[@]}" --no-checkpoint -o "$DIR/$1.png" >"$DIR/$1.out" 2>&1 ||
        { cat "$DIR/$1.out" >&2; echo "ab_render.sh: the render of $1 failed" >&2; exit 1; }
    segment_rate "$DIR/$1.out" >>"$DIR/rates.$1"
    sed -n 's/^image hash: *//p' "$DIR/$1.out" >"$DIR/hash.$1"
}
rm -f "$DIR/rates.a" "$DIR/rates.b"
for ((r = 0; r < ROUNDS; r++)); do
    run a
    run b
done
A=$(median <"$DIR/rates.a")
B=$(median <"$DIR/rates.b")
[ -n "$A" ] && [ -n "$B" ] || { echo "ab_render.sh: no ray segment rate in the output" >&2; exit 1; }
echo "ab_render.sh: rt-mpi ${OPTS[*]}, $ROUNDS alternating rounds, median"
printf '  %-22s %8.3f M segments/s   runs: %s\n' "A (working tree)" "$A" "$(paste -sd' ' "$DIR/rates.a")" \
    "B ($REV = ${COMMIT:0:7})" "$B" "$(paste -sd' ' "$DIR/rates.b")"
printf '  %-22s %8s\n' "A / B speed" "$(ratio "$A" "$B")"
if cmp -s "$DIR/hash.a" "$DIR/hash.b"; then
    echo "  images: identical (hash $(cat "$DIR/hash.a"))"
else
    echo "  images: DIFFER (A $(cat "$DIR/hash.a"), B $(cat "$DIR/hash.b"))"
fi
