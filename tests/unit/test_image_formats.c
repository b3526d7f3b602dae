/* test_image_formats.c - format by extension and option checks; 16-bit PNG
 * and EXR read back by libpng and OpenEXR and compared with the values
 * they must hold (EXR: the linear floats, unclamped, bit for bit); every
 * writer leaves no file, no temporary and the old file untouched when a
 * write fails part way (file size limit) or cannot start. PPM, BMP and PFM
 * are read back by independent readers in e2e_formats.sh. */
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "image.h"
#include "image_write.h"
#include "readers.h"
#include "render.h"
#include "rng.h"
#include "status.h"

#define W 37 /* odd sizes: BMP row padding, a partial last EXR chunk */
#define H 23
#define SPP 3

static int count_files(const char *dir)
{
    char cmd[300];
    snprintf(cmd, sizeof cmd, "exit $(ls -A %s | wc -l)", dir);
    int st = system(cmd);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

int main(void)
{
    /* Extensions, any case; nothing else. */
    CHECK_EQ_INT(rt_image_format_from_path("a.png"), RT_FORMAT_PNG);
    CHECK_EQ_INT(rt_image_format_from_path("dir.exr/A.PNG"), RT_FORMAT_PNG);
    CHECK_EQ_INT(rt_image_format_from_path("a.ppm"), RT_FORMAT_PPM);
    CHECK_EQ_INT(rt_image_format_from_path("a.Bmp"), RT_FORMAT_BMP);
    CHECK_EQ_INT(rt_image_format_from_path("a.pfm"), RT_FORMAT_PFM);
    CHECK_EQ_INT(rt_image_format_from_path("a.exr"), RT_FORMAT_EXR);
    CHECK_EQ_INT(rt_image_format_from_path("a.jpg"), RT_FORMAT_UNKNOWN);
    CHECK_EQ_INT(rt_image_format_from_path("a.png.gz"), RT_FORMAT_UNKNOWN);
    CHECK_EQ_INT(rt_image_format_from_path("png"), RT_FORMAT_UNKNOWN);
    rt_image_write_opts o8 = {.bit_depth = 8}, o16 = {.bit_depth = 16}, ascii = {.bit_depth = 8, .ppm_ascii = 1};
    rt_image_write_opts ascii16 = {.bit_depth = 16, .ppm_ascii = 1}, o12 = {.bit_depth = 12};
    CHECK_EQ_INT(rt_image_check_opts(RT_FORMAT_PNG, &o16), RT_OK);
    CHECK_EQ_INT(rt_image_check_opts(RT_FORMAT_PPM, &ascii16), RT_OK);
    CHECK_EQ_INT(rt_image_check_opts(RT_FORMAT_BMP, &o16), RT_EUNSUPPORTED);
    CHECK_EQ_INT(rt_image_check_opts(RT_FORMAT_EXR, &o16), RT_EUNSUPPORTED);
    CHECK_EQ_INT(rt_image_check_opts(RT_FORMAT_PNG, &ascii), RT_EUNSUPPORTED);
    CHECK_EQ_INT(rt_image_check_opts(RT_FORMAT_PNG, &o12), RT_EINVAL);
    CHECK_EQ_INT(rt_image_check_opts(RT_FORMAT_UNKNOWN, &o8), RT_EUNSUPPORTED);

    /* A render's sums: dark, mid, bright, and radiance far above 1. */
    const size_t n = (size_t)W * H;
    int64_t *acc = malloc(n * 3 * sizeof *acc);
    for (size_t i = 0; i < n * 3; i++) {
        double per_sample = (double)(i * 7919 % 1000) / 400.0; /* 0 to 2.5 */
        if (i % 97 == 0)
            per_sample = 40.0 + i % 13;
        acc[i] = SPP * rt_render_fix(per_sample) + (int64_t)(i % 3);
    }
    uint8_t *rgb8 = malloc(n * 3);
    uint16_t *rgb16 = malloc(n * 3 * sizeof *rgb16);
    float *lin = malloc(n * 3 * sizeof *lin);
    rt_image_to_rgb8(acc, n, SPP, rgb8);
    rt_image_to_rgb16(acc, n, SPP, rgb16);
    rt_image_to_linear(acc, n, SPP, lin);

    char dir[] = "/tmp/rt-formats-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256];

    /* 16-bit PNG through libpng: the exact 16-bit values, whose high bytes
     * are the 8-bit image. */
    snprintf(path, sizeof path, "%s/a16.png", dir);
    CHECK_EQ_INT(rt_image_write(path, acc, W, H, SPP, &o16), RT_OK);
    uint16_t *back16 = NULL;
    uint32_t w = 0, h = 0;
    CHECK_EQ_INT(test_read_png16(path, &back16, &w, &h), 0);
    CHECK_EQ_INT(w, W);
    CHECK_EQ_INT(h, H);
    if (back16) {
        size_t same16 = 0, high_is_8bit = 0;
        for (size_t i = 0; i < n * 3; i++) {
            same16 += back16[i] == rgb16[i];
            high_is_8bit += back16[i] >> 8 == rgb8[i];
        }
        CHECK_EQ_INT(same16, n * 3);
        CHECK_EQ_INT(high_is_8bit, n * 3);
    }
    free(back16);

    /* EXR through OpenEXR's decoder: the linear floats, bit for bit,
     * unclamped (values near 40 survive). */
    snprintf(path, sizeof path, "%s/a.exr", dir);
    CHECK_EQ_INT(rt_image_write(path, acc, W, H, SPP, &o8), RT_OK);
    float *backf = NULL;
    CHECK_EQ_INT(test_read_exr(path, &backf, &w, &h), 0);
    CHECK_EQ_INT(w, W);
    CHECK_EQ_INT(h, H);
    if (backf) {
        CHECK_EQ_INT(memcmp(backf, lin, n * 3 * sizeof *lin), 0);
        float top = 0;
        for (size_t i = 0; i < n * 3; i++)
            top = backf[i] > top ? backf[i] : top;
        CHECK(top > 40.0f);
        CHECK_NEAR(backf[97], lin[97], 0);
    }
    free(backf);

    /* A preview: rows hold different sample counts, rows without samples
     * are black. */
    uint32_t row_samples[H];
    for (uint32_t y = 0; y < H; y++)
        row_samples[y] = y % 3 == 0 ? 0 : y % 3 == 1 ? SPP : 1;
    snprintf(path, sizeof path, "%s/rows.exr", dir);
    CHECK_EQ_INT(rt_image_write_rows(path, acc, W, H, row_samples, &o8), RT_OK);
    CHECK_EQ_INT(test_read_exr(path, &backf, &w, &h), 0);
    if (backf) {
        int rows_ok = 1;
        float want[W * 3];
        for (uint32_t y = 0; y < H; y++) {
            if (row_samples[y])
                rt_image_to_linear(acc + (size_t)y * W * 3, W, row_samples[y], want);
            else
                memset(want, 0, sizeof want);
            rows_ok &= memcmp(backf + (size_t)y * W * 3, want, sizeof want) == 0;
        }
        CHECK(rows_ok);
    }
    free(backf);
    unlink(path);
    CHECK_EQ_INT(count_files(dir), 2);

    /* Failures that cannot start: no file. */
    static const char *const exts[] = {"png", "ppm", "bmp", "pfm", "exr"};
    for (int k = 0; k < 5; k++) {
        snprintf(path, sizeof path, "%s/missing/x.%s", dir, exts[k]);
        CHECK_EQ_INT(rt_image_write(path, acc, W, H, SPP, &o8), RT_EIO);
    }
    snprintf(path, sizeof path, "%s/x.tiff", dir);
    CHECK_EQ_INT(rt_image_write(path, acc, W, H, SPP, &o8), RT_EUNSUPPORTED);
    snprintf(path, sizeof path, "%s/x.bmp", dir);
    CHECK_EQ_INT(rt_image_write(path, acc, W, H, SPP, &o16), RT_EUNSUPPORTED);
    CHECK_EQ_INT(count_files(dir), 2);

    /* Failures part way through (the file size limit stands in for a full
     * disk): an error status, the old file untouched, no temporary left. */
    const uint32_t BW = 300, BH = 200; /* > 64 KiB in every format */
    int64_t *big = calloc((size_t)BW * BH * 3, sizeof *big);
    rt_rng rng = rt_rng_for_stream(5, RT_STREAM_TEST); /* noise: no format can shrink it below the limit */
    for (size_t i = 0; i < (size_t)BW * BH * 3; i++)
        big[i] = rt_render_fix(rt_rng_double(&rng));
    signal(SIGXFSZ, SIG_IGN);
    struct rlimit old, lim;
    CHECK_EQ_INT(getrlimit(RLIMIT_FSIZE, &old), 0);
    for (int k = 0; k < 5; k++) {
        for (int variant = 0; variant < 2; variant++) {
            rt_image_write_opts *o = variant ? (k == 0 ? &o16 : k == 1 ? &ascii : &o8) : &o8;
            snprintf(path, sizeof path, "%s/keep.%s", dir, exts[k]);
            FILE *fp = fopen(path, "wb");
            CHECK(fp && fputs("precious", fp) >= 0 && fclose(fp) == 0);
            lim = old;
            lim.rlim_cur = 4096;
            CHECK_EQ_INT(setrlimit(RLIMIT_FSIZE, &lim), 0);
            int st = rt_image_write(path, big, BW, BH, 1, o);
            CHECK_EQ_INT(setrlimit(RLIMIT_FSIZE, &old), 0);
            /* libpng reports a short write itself (RT_EPNG). */
            if (st != RT_EIO && !(k == 0 && st == RT_EPNG))
                fprintf(stderr, "writing %s (variant %d) past the size limit gave %d\n", exts[k], variant, st);
            CHECK(st == RT_EIO || (k == 0 && st == RT_EPNG));
            struct stat sb;
            CHECK(stat(path, &sb) == 0 && sb.st_size == 8);
            CHECK_EQ_INT(count_files(dir), 3 + k);
            /* And without the limit the same call succeeds. */
            char okpath[300];
            snprintf(okpath, sizeof okpath, "%s/ok.%s", dir, exts[k]);
            CHECK_EQ_INT(rt_image_write(okpath, big, BW, BH, 1, o), RT_OK);
            CHECK(stat(okpath, &sb) == 0 && sb.st_size > 4096);
            unlink(okpath);
        }
    }
    signal(SIGXFSZ, SIG_DFL);

    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    CHECK_EQ_INT(system(cmd), 0);
    free(big);
    free(acc);
    free(rgb8);
    free(rgb16);
    free(lin);
    CHECK_DONE();
}
