#!/bin/bash
# tool_fuzz_build.sh ROOT: tests/fuzz/CMakeLists.txt, the standalone build of
# the fuzz targets that tools/fuzz.sh makes with clang and libFuzzer, keeps
# building over the project's libraries. Built here with the default
# compiler (no libFuzzer: the targets get replay.c's main), unoptimised, and
# each target must then pass its committed corpus and the crashers.
ROOT=$1
source "$(dirname "$0")/../support/lib.sh"
B="$WORK/build-fuzz"
if cmake -S "$ROOT/tests/fuzz" -B "$B" -DCMAKE_BUILD_TYPE=Debug >"$WORK/log" 2>&1 &&
    cmake --build "$B" -j "$(nproc)" >>"$WORK/log" 2>&1; then
    pass "tests/fuzz builds"
else
    fail "tests/fuzz does not build: $(grep -m5 -iE 'error|undefined' "$WORK/log")"
    finish
fi
for t in "fuzz_scene_json corpus" "fuzz_texture_image corpus_texture"; do
    set -- $t
    "$B/$1" "$ROOT/tests/fuzz/$2" "$ROOT/tests/fuzz/crashers" >"$WORK/$1.out" 2>&1
    rc=$?
    check_eq "$1 over tests/fuzz/$2 and the crashers: exit status ($(tail -1 "$WORK/$1.out"))" $rc 0
done
finish
