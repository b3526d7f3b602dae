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
#   ctr     podman run ... mpirun -np 2 rt-mpi --width 96 --height 64 -s 4 -o /tmp/x.png
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
phase_tools() {
    local missing=()
    command -v podman      >/dev/null || missing+=(podman)
    command -v runc        >/dev/null || missing+=(runc)
    command -v debootstrap >/dev/null || missing+=(debootstrap)
    command -v newuidmap   >/dev/null || missing+=(uidmap)
    command -v mpirun      >/dev/null || missing+=(openmpi-bin)
    if [ ${#missing[@]} -eq 0 ]; then
        log "tools present: $(podman --version), $(runc --version | head -n1)"
        return 0
    fi
    if [ "$(id -u)" -ne 0 ]; then
        log "missing ${missing[*]} and not root: cannot install"
        echo "SKIP: missing ${missing[*]} (run as root to install)"
        # In the test command (RT_REQUIRE_ALL=1) a skip is a failure.
        [ "${RT_REQUIRE_ALL:-0}" = 1 ] && exit 1
        exit 77
    fi
    log "installing: ${missing[*]}"
    "$REPO/scripts/install_packages.sh" "${missing[@]}" >"$WORK/apt.log" 2>&1 ||
        { tail -n 30 "$WORK/apt.log" >&2; return 1; }
}

# Mirror the host's apt configuration (the only network reachable here may be
# its configured Debian mirror).
host_mirror() {
    if [ -n "${RT_MPI_MIRROR:-}" ]; then echo "$RT_MPI_MIRROR"; return; fi
    local m=""
    if compgen -G '/etc/apt/sources.list.d/*.sources' >/dev/null; then
        m=$(awk '/^URIs:/ {print $2}' /etc/apt/sources.list.d/*.sources 2>/dev/null \
            | grep -E '/debian/?$' | head -n1 || true)
    fi
    if [ -z "$m" ] && [ -f /etc/apt/sources.list ]; then
        m=$(awk '$1=="deb" {for (i=2;i<=NF;i++) if ($i ~ /^(http|https|file):/) {print $i; break}}' \
            /etc/apt/sources.list | grep -E '/debian/?$' | head -n1 || true)
    fi
    echo "${m:-http://deb.debian.org/debian}"
}

make_base_tar() {
    local mirror root
    mirror=$(host_mirror); mirror=${mirror%/}
    root=$CACHE/rootfs.tmp
    case "$root" in /*/rootfs.tmp) ;; *) log "refusing odd rootfs path '$root'"; return 1 ;; esac
    mkdir -p "$CACHE"
    rm -rf "$root"
    log "debootstrap --variant=minbase bookworm from $mirror"
    nice -n "$NICE" debootstrap --variant=minbase bookworm "$root" "$mirror" >"$CACHE/debootstrap.log" 2>&1 \
        || { tail -n 30 "$CACHE/debootstrap.log" >&2; return 1; }
    # Make it look like the official debian:bookworm-slim: deb822 sources with
    # updates + security, no apt caches, no lists.
    rm -f "$root/etc/apt/sources.list"
    cat >"$root/etc/apt/sources.list.d/debian.sources" <<EOF
Types: deb
URIs: $mirror
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: ${RT_MPI_SECURITY_MIRROR:-${mirror}-security}
Suites: bookworm-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
    cat >"$root/etc/apt/apt.conf.d/docker-clean" <<'EOF'
DPkg::Post-Invoke { "rm -f /var/cache/apt/archives/*.deb /var/cache/apt/archives/partial/*.deb /var/cache/apt/*.bin || true"; };
APT::Update::Post-Invoke { "rm -f /var/cache/apt/archives/*.deb /var/cache/apt/archives/partial/*.deb /var/cache/apt/*.bin || true"; };
Dir::Cache::pkgcache "";
Dir::Cache::srcpkgcache "";
EOF
    # Like the official -slim variant: keep docs/man/locales out of later installs.
    # (Existing copies in the rootfs are left alone; this only affects what the
    # Dockerfile's apt-get installs.)
    printf '%s\n' \
        'path-exclude /usr/share/doc/*' \
        'path-include /usr/share/doc/*/copyright' \
        'path-exclude /usr/share/man/*' \
        'path-exclude /usr/share/groff/*' \
        'path-exclude /usr/share/info/*' \
        'path-exclude /usr/share/lintian/*' \
        'path-exclude /usr/share/linda/*' \
        'path-exclude /usr/share/locale/*' \
        >"$root/etc/dpkg/dpkg.cfg.d/docker"
    rm -rf "${root:?}"/var/lib/apt/lists/* "${root:?}"/var/cache/apt/*.bin "${root:?}"/var/cache/apt/archives/*.deb \
           "${root:?}"/var/log/*.log "${root:?}"/var/log/apt/* "${root:?}"/dev/* "${root:?}"/proc/* "${root:?}"/sys/*
    tar --numeric-owner -C "$root" -cf "$BASE_TAR.tmp" .
    mv "$BASE_TAR.tmp" "$BASE_TAR"
    rm -rf "$root"
    log "base tarball: $BASE_TAR ($(du -h "$BASE_TAR" | cut -f1))"
}

phase_base() {
    if [ "${RT_MPI_REBUILD_BASE:-0}" = 1 ]; then
        rm -f "$BASE_TAR"
        podman image rm -f "$BASE_IMAGE" >/dev/null 2>&1 || true
    fi
    if podman image exists "$BASE_IMAGE"; then
        log "base image $BASE_IMAGE present"
        return 0
    fi
    [ -s "$BASE_TAR" ] || make_base_tar
    log "importing $BASE_TAR as $BASE_IMAGE"
    podman import \
        --change 'ENV PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin' \
        --change 'CMD ["bash"]' \
        "$BASE_TAR" "$BASE_IMAGE" >/dev/null
}

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
        mpirun -np "$NP" rt-mpi "${RENDER_ARGS[@]}" -o /tmp/x.png \
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
