#!/bin/bash
# tool_ab_bvh.sh ROOT: tools/ab_bvh.sh, the A/B timing of BVH versions,
# builds and runs: the working tree against its own bvh.c agrees on every
# ray, and against a copy that skips the last sphere of every leaf (and of
# the spheres outside the tree) it reports the disagreement and fails. (Its timings are printed, never checked.)
ROOT=$1
source "$(dirname "$0")/../support/lib.sh"
export AB_BUILD_DIR="$WORK/build-ab"
AB=(bash "$ROOT/tools/ab_bvh.sh")
"${AB[@]}" "$ROOT/src/core/bvh.c" 40 1 1 >"$WORK/same.out" 2>&1
check_eq "same bvh.c: exit status" $? 0
grep -q "A / B speed" "$WORK/same.out" && pass "prints the speed ratio" || fail "no ratio: $(tail -3 "$WORK/same.out")"
mkdir -p "$WORK/broken"
cp "$ROOT/src/core/bvh_build.c" "$WORK/broken/"
sed '/^static inline int test_spheres/,/^}/ s/i < count;/i + 1 < count;/' \
    "$ROOT/src/core/bvh.c" >"$WORK/broken/bvh.c"
if cmp -s "$ROOT/src/core/bvh.c" "$WORK/broken/bvh.c"; then
    fail "the leaf loop to break was not found in src/core/bvh.c"
else
    "${AB[@]}" "$WORK/broken/bvh.c" 40 1 1 >"$WORK/broken.out" 2>&1
    status=$?
    if [ $status -ne 0 ] && grep -q "A and B disagree on" "$WORK/broken.out"; then
        pass "a broken B is caught: $(grep -o 'disagree on.*' "$WORK/broken.out")"
    else
        fail "broken B: exit status $status, $(tail -2 "$WORK/broken.out")"
    fi
fi
finish
