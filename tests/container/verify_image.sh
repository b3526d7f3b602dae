#!/usr/bin/env bash
# verify_image.sh — build docker/Dockerfile with podman and check that the
# containerised rt-mpi renders the same image as the host build.
#
# Usage: tests/container/verify_image.sh [HOST_RT_MPI_BINARY]
#   HOST_RT_MPI_BINARY defaults to <repo>/build/rt-mpi.
#
# Phases (each timed; summary printed at the end):
#   tools   install podman, runc, debootstrap, uidmap if missing (apt, root only)
#   base    create local image debian:bookworm-slim from a debootstrap --variant=minbase
#           tarball cached in $RT_MPI_CACHE_DIR (no registry needed)
#   build   podman build -f docker/Dockerfile (layer cache makes reruns fast)
#   ctr     podman run ...: the files cmake --install put in /usr/local are there, and
#           mpirun -np 2 rt-mpi --width 96 --height 64 -s 4 -o /tmp/x.png
#   host    mpirun -np 2 HOST_RT_MPI_BINARY (same arguments)
#   compare the 'image hash: ...' lines
#
# Exit codes: 0 PASS, 1 FAIL (mismatch or a phase failed), 77 SKIP (prerequisites
# cannot be installed: not root and podman missing) — register with
# SKIP_RETURN_CODE 77 in CTest.
#
# Logs of the last run (build.log, ctr.out/.err, host.out/.err) are kept in
# $RT_MPI_CACHE_DIR/last-run/.
#
# Environment knobs:
#   RT_MPI_CACHE_DIR   cache dir for the base tarball   (default /var/tmp/rt-mpi-container)
#   RT_MPI_IMAGE       tag of the built image           (default localhost/rt-mpi:verify)
#   RT_MPI_BASE_IMAGE  base image name                  (default debian:bookworm-slim)
#   RT_MPI_BUILD_TAG   tag of the build stage           (default localhost/rt-mpi-build:verify)
#   RT_MPI_MIRROR      Debian mirror for debootstrap    (default: taken from host apt sources)
#   RT_MPI_SECURITY_MIRROR  security mirror for the image (default: $RT_MPI_MIRROR-security)
#   RT_MPI_NP          ranks                             (default 2)
#   RT_MPI_REBUILD_BASE=1  recreate the base tarball and image
#   RT_MPI_NICE        nice level for the heavy phases   (default 10)
# Phase functions are called through timed(); shellcheck cannot see that.
# shellcheck disable=SC2317
set -euo pipefail

SCRIPT_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO=$(cd "$SCRIPT_DIR/../.." && pwd)
HOST_BIN=${1:-$REPO/build/rt-mpi}
CACHE=${RT_MPI_CACHE_DIR:-/var/tmp/rt-mpi-container}
IMAGE=${RT_MPI_IMAGE:-localhost/rt-mpi:verify}
BASE_IMAGE=${RT_MPI_BASE_IMAGE:-debian:bookworm-slim}
BUILD_TAG=${RT_MPI_BUILD_TAG:-localhost/rt-mpi-build:verify}
NP=${RT_MPI_NP:-2}
NICE=${RT_MPI_NICE:-10}
BASE_TAR=$CACHE/debian-bookworm-minbase.tar
RENDER_ARGS=(--width 96 --height 64 -s 4)

# Work-arounds for this kind of host (cgroup v1 hybrid layout, low default ulimits):
# crun fails on it, runc works; rt-mpi/Open MPI need more fds/procs than the default.
PODMAN_RUNTIME=(--runtime runc)
ULIMITS=(--ulimit nofile=20000:20000 --ulimit nproc=32768:32768)

WORK=$(mktemp -d /tmp/rt-mpi-verify.XXXXXX)
LOGDIR=$CACHE/last-run
keep_logs() { # keep the last run's logs for debugging a failed ctest
    if mkdir -p "$LOGDIR" 2>/dev/null; then
        find "$LOGDIR" -maxdepth 1 -type f -delete
        cp "$WORK"/* "$LOGDIR"/ 2>/dev/null || true
    fi
    rm -rf "$WORK"
}
trap keep_logs EXIT

log() { printf '[verify_image] %s\n' "$*" >&2; }
die() { log "ERROR: $*"; echo "FAIL: $*"; exit 1; }

declare -a PHASES=()
now() { date +%s.%N; }
timed() { # timed NAME cmd...
    local name=$1; shift
    local t0 t1 rc=0
    t0=$(now)
    log "phase $name: start"
    "$@" || rc=$?
    t1=$(now)
    local dt
    dt=$(awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.1f", b - a}')
    PHASES+=("$(printf '%-6s %7s s' "$name" "$dt")$([ $rc -ne 0 ] && echo "  (failed rc=$rc)")")
    log "phase $name: done in $dt s (rc=$rc)"
    return $rc
}
summary() {
    echo "timings:"
    local p
    for p in "${PHASES[@]}"; do echo "  $p"; done
}

# ---------------------------------------------------------------------------
# The tools and the base image: base_image.sh (shared with tests/package/test_deb.sh).
source "$SCRIPT_DIR/base_image.sh"

phase_build() {
    # --network host: RUN apt-get must reach the host's mirror.
    # --pull=never: the base image exists only locally; never ask a registry.
    # docker/Dockerfile.dockerignore keeps .git and build trees out of the context.
    # The build stage is tagged too, so that the images a previous run left
    # behind can be removed by id (podman storage stays bounded across reruns
    # while the apt layers stay cached).
    local old_final old_build new id
    old_final=$(podman image inspect --format '{{.Id}}' "$IMAGE" 2>/dev/null || true)
    old_build=$(podman image inspect --format '{{.Id}}' "$BUILD_TAG" 2>/dev/null || true)
    local common=("${PODMAN_RUNTIME[@]}" "${ULIMITS[@]}"
                  --network host --pull=never --layers
                  --build-arg "DEBIAN_IMAGE=$BASE_IMAGE"
                  -f "$REPO/docker/Dockerfile")
    { nice -n "$NICE" podman build "${common[@]}" --target build -t "$BUILD_TAG" "$REPO" &&
      nice -n "$NICE" podman build "${common[@]}" -t "$IMAGE" "$REPO"; } >"$WORK/build.log" 2>&1 \
        || { tail -n 40 "$WORK/build.log" >&2; return 1; }
    for id in "$old_final" "$old_build"; do
        [ -n "$id" ] || continue
        new=$(podman image inspect --format '{{.Id}}' "$IMAGE" "$BUILD_TAG" 2>/dev/null || true)
        if ! grep -qx "$id" <<<"$new"; then podman rmi "$id" >/dev/null 2>&1 || true; fi
    done
    log "built $IMAGE ($(podman image inspect --format '{{.Size}}' "$IMAGE" | awk '{printf "%.0f MB", $1/1e6}'))"
}

phase_ctr() {
    nice -n "$NICE" podman run --rm \
        "${PODMAN_RUNTIME[@]}" "${ULIMITS[@]}" \
        --network none \
        "$IMAGE" \
        sh -c 'for f in bin/rt-mpi share/man/man1/rt-mpi.1 share/rt-mpi/scenes/example.json \
                   share/rt-mpi/slurm/rt-mpi.sbatch; do
                   test -s "/usr/local/$f" || { echo "not installed: /usr/local/$f"; exit 1; }
               done
               n=$1; shift
               exec mpirun -np "$n" rt-mpi "$@" -o /tmp/x.png' sh "$NP" "${RENDER_ARGS[@]}" \
        >"$WORK/ctr.out" 2>"$WORK/ctr.err" \
        || { cat "$WORK/ctr.out" "$WORK/ctr.err" >&2; return 1; }
}

phase_host() {
    [ -x "$HOST_BIN" ] || { log "host binary not found/executable: $HOST_BIN"; return 1; }
    # The image hash does not depend on the MPI transport (the determinism
    # tests show it), so the host runs with the project's usual settings.
    source "$REPO/scripts/mpi_env.sh"
    nice -n "$NICE" mpirun -np "$NP" --oversubscribe --bind-to none "$HOST_BIN" "${RENDER_ARGS[@]}" -o "$WORK/h.png" \
        >"$WORK/host.out" 2>"$WORK/host.err" \
        || { cat "$WORK/host.out" "$WORK/host.err" >&2; return 1; }
}

show_stderr() { # Open MPI / podman warnings are worth seeing even on success
    if [ -s "$1" ]; then log "stderr of $2:"; sed 's/^/    /' "$1" >&2; fi
}
hash_of() { grep -m1 '^image hash:' "$1" | sed 's/^image hash:[[:space:]]*//' || true; }

# ---------------------------------------------------------------------------
log "repo=$REPO host_bin=$HOST_BIN image=$IMAGE base=$BASE_IMAGE np=$NP"
timed tools phase_tools || { summary; die "tools phase failed"; }
timed base  phase_base  || { summary; die "base image phase failed"; }
timed build phase_build || { summary; die "podman build failed"; }
timed ctr   phase_ctr   || { summary; die "container run failed"; }
timed host  phase_host  || { summary; die "host run failed"; }

show_stderr "$WORK/ctr.err" "container run"
show_stderr "$WORK/host.err" "host run"
CTR_HASH=$(hash_of "$WORK/ctr.out")
HOST_HASH=$(hash_of "$WORK/host.out")
summary
echo "container: image hash: ${CTR_HASH:-<missing>}"
echo "host:      image hash: ${HOST_HASH:-<missing>}"
if [ -n "$CTR_HASH" ] && [ "$CTR_HASH" = "$HOST_HASH" ]; then
    echo "PASS: container and host rt-mpi (np=$NP, ${RENDER_ARGS[*]}) print the same image hash"
    exit 0
fi
echo "--- container stdout ---"; cat "$WORK/ctr.out"
echo "--- host stdout ---";      cat "$WORK/host.out"
echo "FAIL: image hash mismatch or missing"
exit 1
