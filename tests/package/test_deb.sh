#!/bin/bash
# test_deb.sh BUILD_DIR HOST_BIN
# The Debian package: `cpack -G DEB` from the build, its control fields
# (the runtime libraries dpkg-shlibdeps found, and openmpi-bin) and files;
# then in a clean Debian 12 container (the base image of the container test,
# tests/container/base_image.sh) `apt-get install ./rt-mpi_*.deb` pulls the
# dependencies from the mirror, and the installed rt-mpi, found on PATH,
# renders under mpirun -np 2 the image the host's binary renders.
# Exit 77 (skip) when podman cannot be had (not root), as the container test.
set -uo pipefail
BUILD=$1 HOST_BIN=$2
MPIRUN=$(command -v mpirun)
SCRIPT_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO=$(cd "$SCRIPT_DIR/../.." && pwd)
source "$REPO/tests/support/lib.sh"
CACHE=${RT_MPI_CACHE_DIR:-/var/tmp/rt-mpi-container}
BASE_IMAGE=${RT_MPI_BASE_IMAGE:-debian:bookworm-slim}
BASE_TAR=$CACHE/debian-bookworm-minbase.tar
NICE=${RT_MPI_NICE:-10}
log() { printf '[test_deb] %s\n' "$*" >&2; }
source "$REPO/tests/container/base_image.sh"
RENDER=(--width 96 --height 64 -s 4 -q --no-checkpoint)

# The package.
mkdir -p "$WORK/pkg"
if ! (cd "$BUILD" && cpack -G DEB -B "$WORK/cpack") >"$WORK/cpack.log" 2>&1; then
    fail "cpack -G DEB: $(tail -5 "$WORK/cpack.log")"
    finish
fi
mv "$WORK"/cpack/rt-mpi_*.deb "$WORK/pkg/"
DEB=$(ls "$WORK"/pkg/rt-mpi_*.deb)
pass "cpack -G DEB: $(basename "$DEB") ($(stat -c %s "$DEB") bytes)"
depends=$(dpkg-deb -f "$DEB" Depends)
missing=""
for d in openmpi-bin libopenmpi3 libpng16-16 libgomp1 libcjson1 libopenexr-3-1-30; do
    grep -q "\(^\|, \)$d\( \|,\|$\)" <<<"$depends" || missing+=" $d"
done
check_eq "Depends: $depends; missing:" "${missing:-none}" none
files=$(dpkg-deb -c "$DEB" | awk '{print $6}')
missing=""
for f in ./usr/bin/rt-mpi ./usr/share/man/man1/rt-mpi.1 ./usr/share/rt-mpi/scenes/example.json \
    ./usr/share/rt-mpi/slurm/rt-mpi.sbatch ./usr/share/doc/rt-mpi/README.md; do
    grep -qx -- "$f" <<<"$files" || missing+=" $f"
done
check_eq "package files; missing:" "${missing:-none}" none

# A clean Debian 12 container installs it with apt and renders.
phase_tools || { fail "installing podman & co"; finish; }
phase_base || { fail "making the base image $BASE_IMAGE"; finish; }
cat >"$WORK/pkg/in-container.sh" <<'EOF'
set -e
cd /pkg
apt-get update -qq
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends ./rt-mpi_*.deb >/tmp/apt.log 2>&1 ||
    { tail -20 /tmp/apt.log; exit 1; }
echo "on PATH: $(command -v rt-mpi)"
rt-mpi --version | sed -n 's/^features: /features: /p'
test -s /usr/share/rt-mpi/scenes/example.json && echo "scenes: /usr/share/rt-mpi/scenes"
cd /tmp
mpirun -np 2 rt-mpi "$@" -o /tmp/x.png
EOF
# Open MPI in a container, as docker/Dockerfile sets it: no CMA, no
# binding, root allowed.
if nice -n "$NICE" podman run --rm --runtime runc --ulimit nofile=20000:20000 --ulimit nproc=32768:32768 \
    --network host -v "$WORK/pkg:/pkg:ro" \
    -e OMPI_ALLOW_RUN_AS_ROOT=1 -e OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 -e OMPI_MCA_pml=ob1 \
    -e OMPI_MCA_btl=self,vader,tcp -e OMPI_MCA_btl_vader_single_copy_mechanism=none \
    -e OMPI_MCA_hwloc_base_binding_policy=none -e OMPI_MCA_rmaps_base_oversubscribe=1 \
    "$BASE_IMAGE" bash /pkg/in-container.sh "${RENDER[@]}" >"$WORK/ctr.out" 2>"$WORK/ctr.err"; then
    pass "apt-get install ./$(basename "$DEB") in a clean $BASE_IMAGE, then mpirun -np 2 rt-mpi"
else
    fail "in the container: $(tail -20 "$WORK/ctr.out" "$WORK/ctr.err")"
fi
check_eq "rt-mpi on PATH in the container" "$(sed -n 's/^on PATH: //p' "$WORK/ctr.out")" /usr/bin/rt-mpi
check_eq "features of the packaged rt-mpi" "$(sed -n 's/^features: //p' "$WORK/ctr.out")" \
    "$("$HOST_BIN" --version | sed -n 's/^features: //p')"
grep -q "^scenes: " "$WORK/ctr.out" && pass "example scenes installed" || fail "no /usr/share/rt-mpi/scenes"
grep -q "^ranks: *2 x" "$WORK/ctr.out" && pass "two ranks in the container: $(grep '^ranks:' "$WORK/ctr.out")" ||
    fail "not two ranks: $(grep '^ranks:' "$WORK/ctr.out")"
mpirun_np 2 "$HOST_BIN" "${RENDER[@]}" -o "$WORK/h.png" >"$WORK/host.out" 2>"$WORK/host.err"
check_eq "image hash: packaged rt-mpi in the container = host build" \
    "$(sed -n 's/^image hash: *//p' "$WORK/ctr.out")" "$(sed -n 's/^image hash: *//p' "$WORK/host.out")"
finish
