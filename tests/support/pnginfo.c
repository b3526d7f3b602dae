/* pnginfo.c - test tool: decodes a PNG with libpng and prints
 * "WIDTHxHEIGHT HASH" (hash of the decoded RGB bytes, as rt-mpi prints it);
 * with --text, prints its text chunks instead, one "KEY=VALUE" per line. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image.h"
#include "readers.h"

static void print_chunk(void *arg, const char *key, const char *text)
{
    (void)arg;
    printf("%s=%s\n", key, text);
}

int main(int argc, char **argv)
{
    int text = argc == 3 && !strcmp(argv[1], "--text");
    if (argc != 2 && !text) {
        fprintf(stderr, "usage: pnginfo [--text] FILE.png\n");
        return 2;
    }
    const char *path = argv[argc - 1];
    if (text) {
        if (test_read_png_text(path, print_chunk, NULL) != 0) {
            fprintf(stderr, "pnginfo: %s: not a readable PNG\n", path);
            return 1;
        }
        return 0;
    }
    uint8_t *rgb;
    uint32_t w, h;
    if (test_read_png8(path, &rgb, &w, &h) != 0) {
        fprintf(stderr, "pnginfo: %s: not a readable 8-bit RGB PNG\n", path);
        return 1;
    }
    printf("%ux%u %016" PRIx64 "\n", w, h, rt_image_hash(rgb, (size_t)w * h * 3));
    free(rgb);
    return 0;
}
