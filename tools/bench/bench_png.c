/* bench_png.c - the PNG writer's time and size at zlib's levels and
 * libpng's row filters, on one image (a binary 8-bit PPM, e.g. a frame
 * rendered with -o frame.ppm), written ROUNDS times each (default 5; the
 * median time is printed). The setting the program uses (RT_PNG_DEFAULT,
 * formats.h) is marked, and the one it used before (level 6, every filter:
 * libpng's and zlib's defaults) is printed first for comparison.
 *   bench_png IMAGE.ppm [ROUNDS] [OUT_DIR] */
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "formats.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static unsigned char *read_ppm(const char *path, uint32_t *w, uint32_t *h)
{
    FILE *f = fopen(path, "rb");
    unsigned maxv = 0;
    if (!f || fscanf(f, "P6 %u %u %u", w, h, &maxv) != 3 || maxv != 255 || fgetc(f) == EOF || !*w || !*h) {
        if (f)
            fclose(f);
        return NULL;
    }
    size_t n = (size_t)*w * *h * 3;
    unsigned char *px = malloc(n);
    if (px && fread(px, 1, n, f) != n) {
        free(px);
        px = NULL;
    }
    fclose(f);
    return px;
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The median seconds of `rounds` writes at p; *bytes gets the file's size. */
static double measure(const char *out, const unsigned char *px, uint32_t w, uint32_t h, rt_png_params p, int rounds,
                      long *bytes)
{
    double t[64];
    for (int r = 0; r < rounds; r++) {
        double t0 = now();
        if (rt_png_write_with(out, px, w, h, 8, NULL, 0, p)) {
            fprintf(stderr, "bench_png: cannot write %s\n", out);
            exit(1);
        }
        t[r] = now() - t0;
    }
    struct stat st;
    *bytes = stat(out, &st) ? -1 : (long)st.st_size;
    qsort(t, (size_t)rounds, sizeof *t, by_value);
    return t[rounds / 2];
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_png IMAGE.ppm [ROUNDS] [OUT_DIR]\n");
        return 2;
    }
    int rounds = argc > 2 ? atoi(argv[2]) : 5;
    if (rounds < 1 || rounds > 64)
        rounds = 5;
    char out[4096];
    snprintf(out, sizeof out, "%s/bench_png.png", argc > 3 ? argv[3] : ".");
    uint32_t w, h;
    unsigned char *px = read_ppm(argv[1], &w, &h);
    if (!px) {
        fprintf(stderr, "bench_png: %s is not a binary 8-bit PPM\n", argv[1]);
        return 2;
    }
    static const struct {
        const char *name;
        int bits;
    } filters[] = {{"all", PNG_ALL_FILTERS}, {"none", PNG_FILTER_NONE}, {"sub", PNG_FILTER_SUB},
                   {"up", PNG_FILTER_UP},    {"paeth", PNG_FILTER_PAETH}};
    const rt_png_params before = {.level = 6, .filters = PNG_ALL_FILTERS}, chosen = RT_PNG_DEFAULT;
    long b0;
    double t0 = measure(out, px, w, h, before, rounds, &b0);
    printf("%ux%u, 8 bits, median of %d writes; raw %zu bytes\n", w, h, rounds, (size_t)w * h * 3);
    printf("%-6s %-6s %9s %11s %8s %8s\n", "level", "filter", "ms", "bytes", "time/b", "size/b");
    printf("%-6d %-6s %9.1f %11ld %8.3f %8.3f  before (zlib's and libpng's defaults)\n", 6, "all", 1e3 * t0, b0, 1.0,
           1.0);
    for (int level = 0; level <= 9; level++)
        for (size_t k = 0; k < sizeof filters / sizeof *filters; k++) {
            rt_png_params p = {.level = level, .filters = filters[k].bits};
            long b;
            double t = measure(out, px, w, h, p, rounds, &b);
            int mark = p.level == chosen.level && p.filters == chosen.filters;
            printf("%-6d %-6s %9.1f %11ld %8.3f %8.3f%s\n", level, filters[k].name, 1e3 * t, b, t / t0,
                   (double)b / (double)b0, mark ? "  <- the program's" : "");
        }
    remove(out);
    free(px);
    return 0;
}
