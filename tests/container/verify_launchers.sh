#!/usr/bin/env bash
# verify_launchers.sh — check the "launcher on the host, one container per rank"
# recipes from docker/README.md on this single node:
#
#   A  host mpirun -np 2 podman run ... rt-mpi ...            (ORTE/PMIx from host mpirun)
#   B  srun --mpi=pmix -n 2 podman run ... rt-mpi ...         (PMIx from slurmd; private
#                                                               test cluster of tests/slurm/slurm_env.sh)
#
# Each must give ONE MPI job of 2 ranks ("ranks: 2 x ...") and the same
# "image hash:" as the host binary. Run tests/container/verify_image.sh first
# (it builds $RT_MPI_IMAGE).
#
# Usage: tests/container/verify_launchers.sh [HOST_RT_MPI_BINARY]
# Exit: 0 all run checks passed, 1 a check failed, 77 image/podman missing.
# B is skipped (not failed) when Slurm is not installed.
set -uo pipefail

SCRIPT_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO=$(cd "$SCRIPT_DIR/../.." && pwd)
HOST_BIN=${1:-$REPO/build/rt-mpi}
IMAGE=${RT_MPI_IMAGE:-localhost/rt-mpi:verify}
ARGS=(--width 96 --height 64 -s 4)

if ! command -v podman >/dev/null || ! podman image exists "$IMAGE"; then
    echo "SKIP: podman or image $IMAGE missing (run verify_image.sh first)"; exit 77
fi

WORK=$(mktemp -d /tmp/rt-mpi-launchers.XXXXXX)
cleanup() { rm -rf "$WORK"; }
trap cleanup EXIT

# Flags every per-rank container needs: the host's network (PMIx/ORTE talk TCP
# on 127.0.0.1 and the BTL on the node's interfaces), IPC + PID namespaces (shared
# memory between ranks on a node), the launcher's environment and its session
# directory, and the same user as the launcher.
POD=(podman run --rm --runtime runc
     --ulimit nofile=20000:20000 --ulimit nproc=32768:32768
     --network host --ipc host --pid host
     --user "$(id -u):$(id -g)"
     -e 'OMPI_*' -e 'PMIX_*' -e 'SLURM_*'
     -v /tmp:/tmp
     --entrypoint /usr/local/bin/rt-mpi)

hash_of() { grep -m1 '^image hash:' "$1" | sed 's/^image hash:[[:space:]]*//'; }
ranks_of() { grep -m1 '^ranks:' "$1" | awk '{print $2}'; }

FAILED=0; PASSED=0
check() { # check NAME OUTFILE
    local h r
    h=$(hash_of "$2"); r=$(ranks_of "$2")
    if [ -n "$h" ] && [ "$h" = "$REF" ] && [ "$r" = 2 ]; then
        echo "PASS: $1 (ranks $r, image hash $h)"; PASSED=$((PASSED + 1))
    else
        echo "FAIL: $1 (ranks ${r:-?}, image hash ${h:-<missing>}, expected 2 ranks and $REF)"
        sed 's/^/    /' "$2"; FAILED=$((FAILED + 1))
    fi
}

ASROOT=()
[ "$(id -u)" -eq 0 ] && ASROOT=(--allow-run-as-root)

"$HOST_BIN" "${ARGS[@]}" -q -o "$WORK/ref.png" >"$WORK/ref.out" 2>&1 \
    || { cat "$WORK/ref.out"; echo "FAIL: host binary $HOST_BIN"; exit 1; }
REF=$(hash_of "$WORK/ref.out")
echo "reference (host, 1 rank): image hash $REF"

# A: host mpirun, a container per rank
cd "$WORK" || exit 1
timeout 300 mpirun "${ASROOT[@]}" -np 2 "${POD[@]}" "$IMAGE" "${ARGS[@]}" -q -o "$WORK/a.png" \
    >"$WORK/a.out" 2>&1
check "A host mpirun -np 2 -> podman run per rank" "$WORK/a.out"

# B: Slurm srun --mpi=pmix, a container per rank (private single-node cluster)
if [ -f "$REPO/tests/slurm/slurm_env.sh" ] && PATH="$PATH:/usr/sbin:/sbin" command -v slurmd >/dev/null; then
    (
        # shellcheck source=/dev/null
        source "$REPO/tests/slurm/slurm_env.sh"
        trap slurm_down EXIT
        slurm_up >"$WORK/slurm_up.log" 2>&1 || { cat "$WORK/slurm_up.log"; exit 1; }
        [ "$SLURM_ENV_MPI" = pmix ] || { echo "no pmix in this Slurm"; exit 3; }
        # PMIx server's files live under slurmd's spool dir: mount it at the same path.
        timeout 300 srun --mpi=pmix -n 2 -p "$SLURM_ENV_PARTITION" \
            "${POD[@]}" -v "$SLURM_ENV_DIR:$SLURM_ENV_DIR" "$IMAGE" "${ARGS[@]}" -q -o "$WORK/b.png"
    ) >"$WORK/b.out" 2>&1
    check "B srun --mpi=pmix -n 2 -> podman run per rank" "$WORK/b.out"
else
    echo "SKIP: B (Slurm not installed; tests/slurm/slurm_env.sh can install it)"
fi

echo "$PASSED passed, $FAILED failed"
[ "$FAILED" -eq 0 ]
