#!/bin/bash
# setup.sh [BUILD_DIR] [cmake options...]
# Installs the Debian 12 packages rt-mpi needs (only those missing), then
# configures and builds with CMake. Safe to run again; prints the binary path.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=${1:-$ROOT/build}
shift || true

PACKAGES=(gcc make cmake pkg-config libopenmpi-dev openmpi-bin libpng-dev)
PACKAGES+=(${RT_EXTRA_PACKAGES:-})

missing=()
for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
    echo "setup: installing ${missing[*]}" >&2
    SUDO=""
    [ "$(id -u)" -eq 0 ] || SUDO="sudo"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release "$@" >&2
cmake --build "$BUILD" -j "$(nproc)" >&2
echo "$BUILD/rt-mpi"
