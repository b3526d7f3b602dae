/* imgread.c - test tool: decodes a 16-bit PNG (libpng) or an EXR (OpenEXR)
 * and writes "WIDTH HEIGHT\n" and the samples for formats_check.py:
 *   imgread png16 IN OUT   big-endian uint16 R, G, B, rows from the top
 *   imgread exr IN OUT     little-endian float32 R, G, B, rows from the top */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "readers.h"

int main(int argc, char **argv)
{
    if (argc != 4 || (strcmp(argv[1], "png16") && strcmp(argv[1], "exr"))) {
        fprintf(stderr, "usage: imgread png16|exr IN OUT\n");
        return 2;
    }
    int png = !strcmp(argv[1], "png16");
    uint16_t *s16 = NULL;
    float *f32 = NULL;
    uint32_t w, h;
    if (png ? test_read_png16(argv[2], &s16, &w, &h) : test_read_exr(argv[2], &f32, &w, &h)) {
        fprintf(stderr, "imgread: %s: cannot decode as %s\n", argv[2], argv[1]);
        return 1;
    }
    size_t n = (size_t)w * h * 3;
    uint8_t *out = malloc(n * 4);
    for (size_t i = 0; i < n && out; i++) {
        if (png) {
            out[2 * i] = (uint8_t)(s16[i] >> 8);
            out[2 * i + 1] = (uint8_t)s16[i];
        } else {
            uint32_t b;
            memcpy(&b, &f32[i], 4);
            for (int k = 0; k < 4; k++)
                out[4 * i + k] = (uint8_t)(b >> (8 * k));
        }
    }
    FILE *fp = fopen(argv[3], "wb");
    int ok = out && fp && fprintf(fp, "%u %u\n", w, h) > 0 && fwrite(out, png ? 2 : 4, n, fp) == n;
    if (fp && fclose(fp) != 0)
        ok = 0;
    free(out);
    free(s16);
    free(f32);
    if (!ok) {
        fprintf(stderr, "imgread: cannot write %s\n", argv[3]);
        return 1;
    }
    return 0;
}
