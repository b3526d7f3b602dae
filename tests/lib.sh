# lib.sh - shared helpers for the end-to-end tests (sourced).
# Every check prints PASS/FAIL with the values involved; the script ends
# with "N passed, N failed" and a non-zero status on any failure.
set -u
PASSED=0
FAILED=0
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_pml=${OMPI_MCA_pml:-ob1}
export OMPI_MCA_rmaps_base_oversubscribe=1
WORK=$(mktemp -d /tmp/rt-e2e.XXXXXX)
trap 'rm -rf "$WORK"' EXIT

pass() { PASSED=$((PASSED + 1)); echo "PASS: $*"; }
fail() { FAILED=$((FAILED + 1)); echo "FAIL: $*"; }
check_eq() { # name got want
    if [ "$2" = "$3" ]; then pass "$1 ($2)"; else fail "$1: got '$2', want '$3'"; fi
}
finish() {
    echo "$PASSED passed, $FAILED failed"
    [ "$FAILED" -eq 0 ]
    exit $?
}
# mpirun with the options a 2-core box needs: ranks may use every core
# (bind-to none) and we may start more ranks than cores.
mpirun_np() { # N args...
    local n=$1
    shift
    timeout 120 "$MPIRUN" -np "$n" --oversubscribe --bind-to none "$@"
}
# A run that must be refused as bad input: exit status 2, one stderr line
# "rt-mpi: error: ..." matching PATTERN (a grep regex), nothing on stdout,
# and no file created in $WORK/out.
expect_usage_error() { # label pattern command...
    local label=$1 pattern=$2 status lines
    shift 2
    rm -rf "$WORK/out" && mkdir -p "$WORK/out"
    "$@" >"$WORK/usage.out" 2>"$WORK/usage.err"
    status=$?
    lines=$(wc -l <"$WORK/usage.err")
    if [ $status -eq 2 ] && [ "$lines" -eq 1 ] && grep -q "^rt-mpi: error: $pattern" "$WORK/usage.err" &&
        [ ! -s "$WORK/usage.out" ] && [ -z "$(ls -A "$WORK/out")" ]; then
        pass "$label -> $(cat "$WORK/usage.err")"
    else
        fail "$label: status $status, $lines stderr lines: $(head -c 300 "$WORK/usage.err"), out: $(ls -A "$WORK/out")"
    fi
}
