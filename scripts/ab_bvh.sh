#!/bin/bash
# ab_bvh.sh [REV | FILE.c] [WIDTH [SAMPLES [ROUNDS]]]
# Decide a BVH change by measurement: times the working tree's src/bvh.c
# against src/bvh.c at git revision REV (default HEAD), or against FILE.c
# (each with its own bvh_traverse.h, see below),
# on the same rays in one process, alternating rounds (tests/ab_bvh.c), and
# fails if the two find different hits. CMake builds both into the target
# ab_bvh with the release flags of the core (-O3, no -march, no FMA
# contraction), without LTO so the call into the BVH is not inlined in
# either; B must keep bvh.h's interface. The build is kept in
# $AB_BUILD_DIR (default build-ab/), so a second run only recompiles B.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
B=${1:-HEAD}
[ $# -gt 0 ] && shift
BUILD=${AB_BUILD_DIR:-$ROOT/build-ab}
mkdir -p "$BUILD"
# B's traversal template (bvh_traverse.h, which bvh.c includes) goes beside
# B's bvh.c, where its #include finds it before src/'s: REV's, or the one
# beside FILE.c; the working tree's when there is none.
if [ -f "$B" ]; then
    cp "$B" "$BUILD/b_bvh.c.new"
    T=$(dirname "$B")/bvh_traverse.h
    [ -f "$T" ] || T=$ROOT/src/bvh_traverse.h
    cp "$T" "$BUILD/bvh_traverse.h.new"
else
    git -C "$ROOT" show "$B:src/bvh.c" >"$BUILD/b_bvh.c.new" || { echo "ab_bvh.sh: no src/bvh.c at '$B'" >&2; exit 2; }
    git -C "$ROOT" show "$B:src/bvh_traverse.h" >"$BUILD/bvh_traverse.h.new" 2>/dev/null ||
        cp "$ROOT/src/bvh_traverse.h" "$BUILD/bvh_traverse.h.new"
fi
# Replace it only when it changed too.
if cmp -s "$BUILD/bvh_traverse.h.new" "$BUILD/bvh_traverse.h"; then
    rm "$BUILD/bvh_traverse.h.new"
else
    mv "$BUILD/bvh_traverse.h.new" "$BUILD/bvh_traverse.h"
    rm -f "$BUILD/b_bvh.c" # so make recompiles B
fi
# Replace B only when it changed, so make does not recompile it for nothing.
if cmp -s "$BUILD/b_bvh.c.new" "$BUILD/b_bvh.c"; then
    rm "$BUILD/b_bvh.c.new"
else
    mv "$BUILD/b_bvh.c.new" "$BUILD/b_bvh.c"
fi
RT_BUILD_TARGET=ab_bvh "$ROOT/scripts/setup.sh" "$BUILD" -DRT_LTO=OFF -DRT_MPI=OFF -DBUILD_TESTING=OFF \
    -DRT_AB_BVH_B="$BUILD/b_bvh.c" >/dev/null 2>"$BUILD/build.log" || { cat "$BUILD/build.log" >&2; exit 2; }
echo "B = ${B}"
"$BUILD/ab_bvh" "$@"
