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
