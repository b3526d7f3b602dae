#!/bin/bash
# ab_bvh.sh [REV | FILE.c] [WIDTH [SAMPLES [ROUNDS]]]
# Decide a BVH change by measurement: times the working tree's BVH
# (src/core/bvh.c and bvh_build.c) against the one at git revision REV
# (default HEAD), or against FILE.c (a bvh.c, with the bvh_build.c and
# headers beside it, see below),
# on the same rays in one process, alternating rounds (tools/bench/ab_bvh.c), and
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
# B's sources: bvh.c, and bvh_build.c where B has one (revisions before the
# build moved out of bvh.c have none: their bvh.c is the whole BVH). The
# headers B may have changed (its interface bvh.h, the layout bvh_node.h, the traversal template
# bvh_traverse.h, the sphere test sphere.h) go beside them, where their
# #include finds them before src/'s: REV's, or the ones beside FILE.c; the
# working tree's where there are none.
HEADERS="bvh.h bvh_node.h bvh_traverse.h sphere.h"
rm -f "$BUILD/b_bvh_build.c.new"
if [ -f "$B" ]; then
    D=$(dirname "$B")
    cp "$B" "$BUILD/b_bvh.c.new"
    [ -f "$D/bvh_build.c" ] && cp "$D/bvh_build.c" "$BUILD/b_bvh_build.c.new"
    for h in $HEADERS; do
        T=$D/$h
        [ -f "$T" ] || T=$ROOT/src/core/$h
        cp "$T" "$BUILD/$h.new"
    done
else
    # src/core/ since the layout change; src/ in revisions before it
    D=src/core
    git -C "$ROOT" cat-file -e "$B:$D/bvh.c" 2>/dev/null || D=src
    git -C "$ROOT" show "$B:$D/bvh.c" >"$BUILD/b_bvh.c.new" || { echo "ab_bvh.sh: no bvh.c at '$B'" >&2; exit 2; }
    git -C "$ROOT" show "$B:$D/bvh_build.c" >"$BUILD/b_bvh_build.c.new" 2>/dev/null || rm -f "$BUILD/b_bvh_build.c.new"
    for h in $HEADERS; do
        git -C "$ROOT" show "$B:$D/$h" >"$BUILD/$h.new" 2>/dev/null || cp "$ROOT/src/core/$h" "$BUILD/$h.new"
    done
fi
B_SOURCES="$BUILD/b_bvh.c"
if [ -f "$BUILD/b_bvh_build.c.new" ]; then
    B_SOURCES+=";$BUILD/b_bvh_build.c"
else
    rm -f "$BUILD/b_bvh_build.c"
fi
# Each file replaces the build's copy only when it changed, so make does
# not recompile B for nothing; a changed header gives B a fresh copy too, so
# it is recompiled even when make did not yet know it depends on the header.
replace_if_changed() { # file: install file.new as file; status 0 when it changed
    if cmp -s "$1.new" "$1"; then
        rm "$1.new"
        return 1
    fi
    mv "$1.new" "$1"
}
for h in $HEADERS; do
    replace_if_changed "$BUILD/$h" && rm -f "$BUILD/b_bvh.c" "$BUILD/b_bvh_build.c"
done
replace_if_changed "$BUILD/b_bvh.c" || true
[ -f "$BUILD/b_bvh_build.c.new" ] && { replace_if_changed "$BUILD/b_bvh_build.c" || true; }
RT_BUILD_TARGET=ab_bvh "$ROOT/scripts/setup.sh" "$BUILD" -DRT_LTO=OFF -DRT_MPI=OFF -DBUILD_TESTING=OFF \
    -DRT_AB_BVH_B="$B_SOURCES" >/dev/null 2>"$BUILD/build.log" || { cat "$BUILD/build.log" >&2; exit 2; }
echo "B = ${B}"
"$BUILD/ab_bvh" "$@"
