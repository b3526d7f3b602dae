#!/bin/bash
# fuzz.sh [SECONDS] [TARGET] - fuzzes the scene-file loader (TARGET
# scene_json, the default) or the image-texture reader (texture) with
# libFuzzer. Builds tests/fuzz with clang (-fsanitize=fuzzer,address,undefined)
# into build-fuzz, runs it from the committed corpus for SECONDS (default
# 300), then merges the inputs that reach new code into the corpus
# (tests/fuzz/corpus, or tests/fuzz/corpus_texture).
# Crashing inputs land in tests/fuzz/crashers/: commit them with the fix,
# and ctest's unit_scene_json_corpus and unit_texture_image_corpus keep them
# from coming back.
# Needs clang and its fuzzer runtime:
#   RT_EXTRA_PACKAGES="clang-14 libclang-rt-14-dev libomp-14-dev" scripts/setup.sh
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
SECONDS_TO_RUN=${1:-300}
FUZZ="$ROOT/tests/fuzz"
CC=${CC:-clang-14} cmake -S "$FUZZ" -B "$ROOT/build-fuzz" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$ROOT/build-fuzz" >/dev/null
NEW=$(mktemp -d)
trap 'rm -rf "$NEW"' EXIT
case ${2:-scene_json} in
    scene_json) BIN=fuzz_scene_json CORPUS=$FUZZ/corpus EXTRA=(-dict="$FUZZ/scene_json.dict") ;;
    texture) BIN=fuzz_texture_image CORPUS=$FUZZ/corpus_texture EXTRA=() ;;
    *) echo "fuzz.sh: unknown target '$2' (scene_json or texture)" >&2; exit 2 ;;
esac
"$ROOT/build-fuzz/$BIN" -max_total_time="$SECONDS_TO_RUN" -max_len=8192 -timeout=10 \
    "${EXTRA[@]}" -artifact_prefix="$FUZZ/crashers/" -print_final_stats=1 \
    "$NEW" "$CORPUS"
"$ROOT/build-fuzz/$BIN" -merge=1 "$CORPUS" "$NEW" 2>&1 | grep -E "MERGE-OUTER: [0-9]+ new files" || true
echo "corpus: $(ls "$CORPUS" | wc -l) files, $(du -sh "$CORPUS" | cut -f1)"
