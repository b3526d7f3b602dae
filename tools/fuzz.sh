#!/bin/bash
# fuzz.sh [SECONDS] - fuzzes the scene-file loader with libFuzzer.
# Builds tests/fuzz with clang (-fsanitize=fuzzer,address,undefined) into
# build-fuzz, runs it from the committed corpus for SECONDS (default 300),
# then merges the inputs that reach new code into tests/fuzz/corpus.
# Crashing inputs land in tests/fuzz/crashers/: commit them with the fix,
# and ctest's fuzz_replay keeps them from coming back.
# Needs clang and its fuzzer runtime:
#   RT_EXTRA_PACKAGES="clang-14 libclang-rt-14-dev" scripts/setup.sh
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
SECONDS_TO_RUN=${1:-300}
FUZZ="$ROOT/tests/fuzz"
CC=${CC:-clang-14} cmake -S "$FUZZ" -B "$ROOT/build-fuzz" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$ROOT/build-fuzz" >/dev/null
NEW=$(mktemp -d)
trap 'rm -rf "$NEW"' EXIT
"$ROOT/build-fuzz/fuzz_scene_json" -max_total_time="$SECONDS_TO_RUN" -max_len=8192 -timeout=10 \
    -dict="$FUZZ/scene_json.dict" -artifact_prefix="$FUZZ/crashers/" -print_final_stats=1 \
    "$NEW" "$FUZZ/corpus"
"$ROOT/build-fuzz/fuzz_scene_json" -merge=1 "$FUZZ/corpus" "$NEW" 2>&1 | grep -E "MERGE-OUTER: [0-9]+ new files" || true
echo "corpus: $(ls "$FUZZ/corpus" | wc -l) files, $(du -sh "$FUZZ/corpus" | cut -f1)"
