#!/bin/bash
# test.sh: from a fresh Debian 12 machine, installs what is missing, builds
# and runs the whole test suite: ctest (unit tests, end-to-end tests under
# mpirun, checkpoint/resume/signals, Slurm, ...), then the sanitizer and
# valgrind pass (tools/sanitize.sh).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# What the tests need beyond the build: a real single-node Slurm, valgrind,
# python3 for JSON checks and the scaling scripts, matplotlib for trace
# plots, podman and debootstrap for the container image and the Debian
# package, dpkg-dev (dpkg-shlibdeps) for cpack, groff for the man page.
export RT_EXTRA_PACKAGES="${RT_EXTRA_PACKAGES:-} slurm-wlm munge valgrind python3 python3-matplotlib"
RT_EXTRA_PACKAGES+=" podman runc debootstrap uidmap dpkg-dev groff-base"
# The cluster label: namespaces, veth, bridge and tc (iproute2), nsenter and
# unshare (util-linux), python3 for the bad-link emulator.
RT_EXTRA_PACKAGES+=" iproute2 util-linux"
"$ROOT/scripts/setup.sh" "$ROOT/build" -DBUILD_TESTING=ON >/dev/null
# Every test must run here: a test that would skip (no permission, a
# missing tool) fails instead, so CI cannot pass on skipped checks.
export RT_REQUIRE_ALL=1
(cd "$ROOT/build" && ctest --output-on-failure --timeout 600 "$@")
"$ROOT/tools/sanitize.sh"
