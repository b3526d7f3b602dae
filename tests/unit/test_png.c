/* test_png.c - PNG written with libpng and read back; text chunks; failed
 * writes leave no file and never clobber an existing one. */
#include <png.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "formats.h"
#include "readers.h"
#include "status.h"

typedef struct wanted {
    const char *key, *value;
    int found;
} wanted;

static void match_chunk(void *arg, const char *key, const char *text)
{
    wanted *w = arg;
    w->found += !strcmp(key, w->key) && !strcmp(text, w->value);
}

/* Text chunks of the file with that key and value; -1 if unreadable. */
static int count_text(const char *path, const char *key, const char *value)
{
    wanted w = {key, value, 0};
    return test_read_png_text(path, match_chunk, &w) ? -1 : w.found;
}

int main(void)
{
    char dir[] = "/tmp/rt-png-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256];
    snprintf(path, sizeof path, "%s/a.png", dir);
    const uint32_t W = 37, H = 23;
    uint8_t *rgb = malloc(W * H * 3);
    for (uint32_t i = 0; i < W * H * 3; i++)
        rgb[i] = (uint8_t)(i * 31 + i / 7);
    rt_text text[] = {{"Software", "rt-mpi test"}, {"rt-mpi:seed", "42"}};
    CHECK_EQ_INT(rt_png_write(path, rgb, W, H, 8, text, 2), RT_OK);
    uint8_t *back = NULL;
    uint32_t w = 0, h = 0;
    CHECK_EQ_INT(test_read_png8(path, &back, &w, &h), RT_OK);
    CHECK_EQ_INT(w, W);
    CHECK_EQ_INT(h, H);
    CHECK(back && memcmp(back, rgb, W * H * 3) == 0);
    CHECK_EQ_INT(count_text(path, "rt-mpi:seed", "42"), 1);
    CHECK_EQ_INT(count_text(path, "Software", "rt-mpi test"), 1);
    free(back);

    /* 16-bit write is a valid PNG (read by libpng at 16 bits). */
    uint16_t *rgb16 = malloc(W * H * 3 * sizeof *rgb16);
    for (uint32_t i = 0; i < W * H * 3; i++)
        rgb16[i] = (uint16_t)(i * 977);
    char p16[256];
    snprintf(p16, sizeof p16, "%s/b16.png", dir);
    CHECK_EQ_INT(rt_png_write(p16, rgb16, W, H, 16, NULL, 0), RT_OK);
    FILE *fp = fopen(p16, "rb");
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    CHECK(fp && png_image_begin_read_from_stdio(&img, fp));
    img.format = PNG_FORMAT_LINEAR_RGB;
    uint16_t *r16 = malloc(PNG_IMAGE_SIZE(img));
    CHECK(png_image_finish_read(&img, NULL, r16, 0, NULL));
    /* A 16-bit PNG without gAMA is linear to libpng, so the samples come back
     * as written: this catches a wrong byte order (png_set_swap) too. */
    CHECK_EQ_INT(img.width, W);
    CHECK(memcmp(r16, rgb16, W * H * 3 * sizeof *rgb16) == 0);
    fclose(fp);
    free(r16);
    free(rgb16);

    /* A failed write (missing directory) creates nothing. */
    char bad[256];
    snprintf(bad, sizeof bad, "%s/missing/x.png", dir);
    CHECK(rt_png_write(bad, rgb, W, H, 8, NULL, 0) != RT_OK);
    CHECK(access(bad, F_OK) != 0);
    /* A failed write never clobbers the existing file: bad parameters. */
    struct stat before, after;
    stat(path, &before);
    CHECK_EQ_INT(rt_png_write(path, rgb, 0, H, 8, NULL, 0), RT_EINVAL);
    stat(path, &after);
    CHECK_EQ_INT(after.st_size, before.st_size);
    /* The zlib level and filters reach libpng: level 0 stores the rows
     * (a file larger than the pixels), level 9 compresses this periodic
     * image; the program's setting is what rt_png_write writes, and its
     * filters are png.h's PNG_ALL_FILTERS (formats.h spells the value). */
    CHECK_EQ_INT(RT_PNG_DEFAULT.filters, PNG_ALL_FILTERS);
    long sizes[3];
    const rt_png_params levels[3] = {{.level = 0, .filters = PNG_FILTER_NONE},
                                     {.level = 9, .filters = PNG_ALL_FILTERS}, RT_PNG_DEFAULT};
    for (int k = 0; k < 3; k++) {
        CHECK_EQ_INT(rt_png_write_with(p16, rgb, W, H, 8, NULL, 0, levels[k]), RT_OK);
        stat(p16, &after);
        sizes[k] = (long)after.st_size;
    }
    CHECK(sizes[0] > (long)(W * H * 3));
    CHECK(sizes[1] < (long)(W * H * 3) / 2);
    CHECK_EQ_INT(rt_png_write(p16, rgb, W, H, 8, NULL, 0), RT_OK);
    stat(p16, &after);
    CHECK_EQ_INT(after.st_size, sizes[2]);
    CHECK_EQ_INT(rt_png_write_with(p16, rgb, W, H, 8, NULL, 0, (rt_png_params){.level = 10, .filters = PNG_ALL_FILTERS}),
                 RT_EINVAL);
    CHECK_EQ_INT(rt_png_write_with(p16, rgb, W, H, 8, NULL, 0, (rt_png_params){.level = 4, .filters = 0}), RT_EINVAL);
    /* No temporary files left behind. */
    char cmd[512];
    snprintf(cmd, sizeof cmd, "test $(ls %s | wc -l) -eq 2", dir);
    CHECK_EQ_INT(system(cmd), 0);
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    CHECK_EQ_INT(system(cmd), 0);
    free(rgb);
    CHECK_DONE();
}
