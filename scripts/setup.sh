#!/bin/bash
# setup.sh [BUILD_DIR] [cmake options...]
# Installs the Debian 12 packages rt-mpi needs (only those missing), then
# configures and builds with CMake (only target $RT_BUILD_TARGET if set).
# Safe to run again; prints the binary path.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=${1:-$ROOT/build}
shift || true

PACKAGES=(gcc make cmake pkg-config libopenmpi-dev openmpi-bin libpng-dev)
# Optional features, used when present: scene files and --stats/--trace
# (cJSON), OpenEXR output, JPEG image textures (libjpeg-turbo).
PACKAGES+=(libcjson-dev libopenexr-dev libjpeg62-turbo-dev)
# The tests read files back with ImageMagick, python3 and OpenEXR's tools.
# The fuzzer (tools/fuzz.sh) also needs clang and its OpenMP:
# RT_EXTRA_PACKAGES="clang-14 libclang-rt-14-dev libomp-14-dev".
case " $* " in *" -DBUILD_TESTING=ON "*) PACKAGES+=(imagemagick python3 openexr) ;; esac
PACKAGES+=(${RT_EXTRA_PACKAGES:-})

"$ROOT/scripts/install_packages.sh" "${PACKAGES[@]}"

cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release "$@" >&2
# RT_BUILD_TARGET: build only that target (and what it needs).
cmake --build "$BUILD" -j "$(nproc)" ${RT_BUILD_TARGET:+--target "$RT_BUILD_TARGET"} >&2
echo "$BUILD/rt-mpi"
