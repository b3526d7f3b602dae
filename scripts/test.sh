#!/bin/bash
# test.sh: from a fresh Debian 12 machine, installs what is missing, builds
# and runs the whole test suite (unit, MPI end-to-end, ...) with ctest.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$ROOT/scripts/setup.sh" "$ROOT/build" -DBUILD_TESTING=ON >/dev/null
cd "$ROOT/build"
ctest --output-on-failure --timeout 600 "$@"
