/* pnginfo.c - test tool: decodes a PNG with libpng and prints
 * "WIDTHxHEIGHT HASH" (hash of the decoded RGB bytes, as rt-mpi prints it). */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>

#include "image.h"
#include "image_io.h"

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: pnginfo FILE.png\n");
        return 2;
    }
    uint8_t *rgb;
    uint32_t w, h;
    if (rt_png_read(argv[1], &rgb, &w, &h) != 0) {
        fprintf(stderr, "pnginfo: %s: not a readable 8-bit RGB PNG\n", argv[1]);
        return 1;
    }
    printf("%ux%u %016" PRIx64 "\n", w, h, rt_image_hash(rgb, (size_t)w * h * 3));
    free(rgb);
    return 0;
}
