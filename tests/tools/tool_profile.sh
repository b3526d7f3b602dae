#!/bin/bash
# tool_profile.sh ROOT: tools/profile.sh, the callgrind instruction counts
# the README quotes, builds and runs: the intersector is called once per ray
# segment (the script checks this itself, against --stats), and the counts
# tell the intersectors apart as they must: brute force tests every sphere
# of the scene, the BVH a few. (No timing is checked.)
ROOT=$1
source "$(dirname "$0")/../support/lib.sh"
export PROFILE_BUILD_DIR="$WORK/build-profile"
P=(bash "$ROOT/tools/profile.sh" --width 40 --height 26 -s 2)
"${P[@]}" >"$WORK/bvh.out" 2>&1
check_eq "profile.sh (bvh): exit status" $? 0
"${P[@]}" --accel brute >"$WORK/brute.out" 2>&1
check_eq "profile.sh (brute): exit status" $? 0
per_query() { awk '/in the intersector, per query/ {print int($NF)}' "$1"; }
bvh=$(per_query "$WORK/bvh.out")
brute=$(per_query "$WORK/brute.out")
# the spheres of the scene profiled (the final scene with default options)
"$PROFILE_BUILD_DIR/rt-mpi" --dump-scene "$WORK/scene.json" >/dev/null
spheres=$(python3 -c 'import json, sys; print(len(json.load(open(sys.argv[1]))["spheres"]))' "$WORK/scene.json")
echo "instructions per query: bvh ${bvh:-?}, brute force ${brute:-?}; ${spheres:-?} spheres"
if [ -n "$bvh" ] && [ -n "$brute" ] && [ -n "$spheres" ]; then
    # a sphere test is at least 10 instructions
    [ "$brute" -gt $((spheres * 10)) ] && pass "brute force: $brute instructions per query (> $spheres spheres x 10)" ||
        fail "brute force: $brute instructions per query, too few for $spheres sphere tests"
    [ "$bvh" -gt 0 ] && [ $((bvh * 10)) -lt "$brute" ] && pass "bvh: $bvh instructions per query (< brute / 10)" ||
        fail "bvh: $bvh instructions per query against $brute for brute force"
else
    fail "no per-query counts: $(tail -2 "$WORK/bvh.out") $(tail -2 "$WORK/brute.out")"
fi
finish
