#!/bin/bash
# tool_lockstep_probe.sh ROOT RT_MPI: tools/lockstep_probe.sh, the issue-35
# probe docs/notes/experiments.md quotes, builds against src/core's sampler
# and runs: its lanes trace the same segments as its scalar loop to the bit
# (the script checks a fingerprint of every hit and exits 1 otherwise), and
# it prints a row of numbers for each loop. On a CPU without AVX-512 it must
# refuse with one line and exit 2. (No timing is checked.)
ROOT=$1 RT=$2
source "$(dirname "$0")/../support/lib.sh"
bash "$ROOT/tools/lockstep_probe.sh" --rounds 1 --bin "$RT" >"$WORK/out" 2>"$WORK/err"
rc=$?
if grep -q avx512dq /proc/cpuinfo && grep -q avx512f /proc/cpuinfo; then
    check_eq "lockstep_probe.sh: exit status ($(head -c 300 "$WORK/err"))" $rc 0
    grep -q "^scalar and lanes: the same segments" "$WORK/out" && pass "scalar and lanes: the same segments" ||
        fail "no agreement line: $(cat "$WORK/out")"
    rows=$(grep -cE '^(rt-mpi|scalar|lanes|sobol) +[0-9.]+ +[0-9.]+ +[0-9.]+$' "$WORK/out")
    check_eq "rows of numbers (rt-mpi, scalar, lanes, sobol)" "$rows" 4
else
    check_eq "lockstep_probe.sh without AVX-512: exit status" $rc 2
    grep -q "error: this CPU has no AVX-512" "$WORK/err" && pass "one error line" || fail "stderr: $(cat "$WORK/err")"
fi
finish
