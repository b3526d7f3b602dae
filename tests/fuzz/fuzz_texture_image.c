/* fuzz_texture_image.c - libFuzzer target for the image-texture reader
 * (built by tests/fuzz/CMakeLists.txt with clang; see tools/fuzz.sh). */
#include <stdio.h>
#include <stdlib.h>

#include "texture_image_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *bad = fuzz_texture_image_check(data, size);
    if (bad) {
        fprintf(stderr, "property broken: %s\n", bad);
        abort();
    }
    return 0;
}
