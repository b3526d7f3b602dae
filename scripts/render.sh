#!/bin/bash
# render.sh [rt-mpi options...]
# From a fresh Debian 12 machine: installs what is missing, builds, and
# renders the default scene (book 1 final scene, 1200x800) in one process
# using every core of this machine into output.png, at 100 samples per pixel unless
# the options say otherwise (the last -s or -o given wins); the full
# 500-spp job is
#   scripts/render.sh -s 500
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# Only the program is built (scripts/test.sh builds the tests).
BIN=$(RT_BUILD_TARGET=rt-mpi "$ROOT/scripts/setup.sh" "$ROOT/build")
# One process here: its OpenMP threads use every core (see README for
# mpirun and Slurm).
"$BIN" -o "$ROOT/output.png" -s 100 "$@"
