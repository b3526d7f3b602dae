#!/bin/bash
# ab_bvh.sh [REV | FILE.c] [WIDTH [SAMPLES [ROUNDS]]]
# Decide a BVH change by measurement: times the working tree's src/bvh.c
# against src/bvh.c at git revision REV (default HEAD), or against FILE.c,
# on the same rays in one process, alternating rounds (tests/ab_bvh.c), and
# fails if the two find different hits. Both are built with the release
# flags (-O3, no -march, no FMA contraction; without LTO, so the call into
# the BVH is not inlined in either). B must keep bvh.h's interface.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
B=${1:-HEAD}
[ $# -gt 0 ] && shift
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
if [ -f "$B" ]; then
    cp "$B" "$TMP/b_bvh.c"
else
    git -C "$ROOT" show "$B:src/bvh.c" >"$TMP/b_bvh.c" || { echo "ab_bvh.sh: no src/bvh.c at '$B'" >&2; exit 2; }
fi
"$ROOT/scripts/install_packages.sh" gcc
CFLAGS=(-O3 -DNDEBUG -std=c11 -D_POSIX_C_SOURCE=200809L -ffp-contract=off -fno-math-errno -fopenmp -I"$ROOT/src")
RENAME=()
for f in build free closest closest_portable bytes stats; do RENAME+=(-Drt_bvh_$f=ab_bvh_$f); done
gcc "${CFLAGS[@]}" "${RENAME[@]}" -c "$TMP/b_bvh.c" -o "$TMP/b_bvh.o"
S=$ROOT/src
gcc "${CFLAGS[@]}" "$ROOT/tests/ab_bvh.c" "$TMP/b_bvh.o" $S/{status,scene,camera,material,accel,bvh,render,scenes,progress}.c \
    -lm -o "$TMP/ab_bvh"
echo "B = ${B}"
"$TMP/ab_bvh" "$@"
