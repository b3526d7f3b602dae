#!/bin/bash
# sanitize.sh: builds rt-mpi with AddressSanitizer + UndefinedBehaviorSanitizer
# (build-asan/) and runs the unit tests and an `mpirun -np 2` render under
# them, then a small render under valgrind memcheck (release build). Any
# report fails the script. Part of scripts/test.sh.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
RT_EXTRA_PACKAGES="valgrind" "$ROOT/scripts/setup.sh" "$ROOT/build-asan" -DRT_SANITIZE=ON -DBUILD_TESTING=ON \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
source "$ROOT/scripts/mpi_env.sh"
# The release build's serial program for valgrind (built, or brought up to
# date, here: running this script alone must not test a stale binary).
"$ROOT/scripts/setup.sh" "$ROOT/build" -DBUILD_TESTING=ON >/dev/null
cmake --build "$ROOT/build" --target rt-mpi-serial >/dev/null
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

echo "== unit tests under ASan + UBSan (leak checking on)"
(cd "$ROOT/build-asan" && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 ctest -L unit --output-on-failure)

echo "== mpirun -np 2 render under ASan + UBSan"
# Open MPI's own start-up allocations are never freed; leak checking of the
# MPI program would only report those, so it is off here (the unit tests
# above cover our code's leaks).
ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 mpirun -np 2 --oversubscribe --bind-to none \
    -x ASAN_OPTIONS -x UBSAN_OPTIONS "$ROOT/build-asan/rt-mpi" --width 64 --height 40 -s 4 -j 2 -q \
    -o "$TMP/asan.png" --no-checkpoint >"$TMP/asan.out" 2>"$TMP/asan.err" || {
    echo "FAIL: sanitized mpirun render"; cat "$TMP/asan.err"; exit 1; }
if grep -E "ERROR: AddressSanitizer|runtime error:" "$TMP/asan.err"; then
    echo "FAIL: sanitizer report"; exit 1
fi
echo "PASS: sanitized mpirun -np 2 render: $(grep 'image hash' "$TMP/asan.out")"

echo "== valgrind memcheck of a small single-process render"
valgrind --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite \
    "$ROOT/build/tests/rt-mpi-serial" --width 48 --height 32 -s 2 -j 1 -q -o "$TMP/vg.png" \
    --no-checkpoint >"$TMP/vg.out" 2>"$TMP/vg.err" || {
    echo "FAIL: valgrind memcheck (status $?)"; tail -30 "$TMP/vg.err"; exit 1; }
grep -E "ERROR SUMMARY" "$TMP/vg.err"
echo "PASS: memcheck clean"
echo "3 passed, 0 failed"
