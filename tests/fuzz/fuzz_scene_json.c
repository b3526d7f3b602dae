/* fuzz_scene_json.c - libFuzzer target for the scene-file loader (built by
 * tests/fuzz/CMakeLists.txt with clang; see tools/fuzz.sh). */
#include <stdio.h>
#include <stdlib.h>

#include "scene_json_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *bad = fuzz_scene_json_check(data, size);
    if (bad) {
        fprintf(stderr, "property broken: %s\n", bad);
        abort();
    }
    return 0;
}
