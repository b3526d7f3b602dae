/* readers.c - libpng and OpenEXR decoders for the tests (see readers.h). */
#include "readers.h"

#include <openexr.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>

int test_read_png_text(const char *path, void (*fn)(void *arg, const char *key, const char *text), void *arg)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return -1;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    int rc = -1;
    if (info && !setjmp(png_jmpbuf(png))) {
        png_init_io(png, fp);
        png_read_info(png, info);
        png_textp t;
        int n = 0;
        png_get_text(png, info, &t, &n);
        for (int i = 0; i < n; i++)
            fn(arg, t[i].key, t[i].text);
        rc = 0;
    }
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    return rc;
}

/* An RGB PNG of the given bit depth, no transforms: samples as stored
 * (16-bit ones big-endian in the file, host order in *out). */
static int read_png_rgb(const char *path, int depth, void **out_rgb, uint32_t *w, uint32_t *h)
{
    *out_rgb = NULL;
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return -1;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    uint8_t *volatile row = NULL;
    uint8_t *volatile out = NULL;
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, &info, NULL);
        fclose(fp);
        free(row);
        free(out);
        return -1;
    }
    png_init_io(png, fp);
    png_read_info(png, info);
    if (png_get_bit_depth(png, info) != depth || png_get_color_type(png, info) != PNG_COLOR_TYPE_RGB ||
        png_get_interlace_type(png, info) != PNG_INTERLACE_NONE)
        png_error(png, "not an RGB PNG of the expected depth");
    *w = png_get_image_width(png, info);
    *h = png_get_image_height(png, info);
    const size_t bytes = (size_t)depth / 8, n = (size_t)*w * 3;
    row = malloc(n * bytes);
    out = malloc(n * *h * bytes);
    if (!row || !out)
        png_error(png, "out of memory");
    for (uint32_t y = 0; y < *h; y++) {
        png_read_row(png, row, NULL);
        if (depth == 8) {
            memcpy(out + (size_t)y * n, row, n);
            continue;
        }
        uint16_t *dst = (uint16_t *)out + (size_t)y * n;
        for (size_t i = 0; i < n; i++)
            dst[i] = (uint16_t)(row[2 * i] << 8 | row[2 * i + 1]);
    }
    png_read_end(png, NULL);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    free(row);
    *out_rgb = out;
    return 0;
}

int test_read_png16(const char *path, uint16_t **rgb, uint32_t *w, uint32_t *h)
{
    void *p;
    int r = read_png_rgb(path, 16, &p, w, h);
    *rgb = p;
    return r;
}

int test_read_png8(const char *path, uint8_t **rgb, uint32_t *w, uint32_t *h)
{
    void *p;
    int r = read_png_rgb(path, 8, &p, w, h);
    *rgb = p;
    return r;
}

int test_read_exr(const char *path, float **rgb, uint32_t *w, uint32_t *h)
{
    *rgb = NULL;
    exr_context_t ctx;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    if (exr_start_read(&ctx, path, &init) != EXR_ERR_SUCCESS)
        return -1;
    exr_attr_box2i_t dw;
    int32_t lines = 0;
    exr_result_t rv = exr_get_data_window(ctx, 0, &dw);
    if (!rv)
        rv = exr_get_scanlines_per_chunk(ctx, 0, &lines);
    if (rv || lines <= 0) {
        exr_finish(&ctx);
        return -1;
    }
    *w = (uint32_t)(dw.max.x - dw.min.x + 1);
    *h = (uint32_t)(dw.max.y - dw.min.y + 1);
    float *out = calloc((size_t)*w * *h * 3, sizeof *out);
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    int started = 0, found = 0;
    for (int32_t y = dw.min.y; y <= dw.max.y && out && !rv; y += lines) {
        exr_chunk_info_t ci;
        rv = exr_read_scanline_chunk_info(ctx, 0, y, &ci);
        if (!rv)
            rv = started ? exr_decoding_update(ctx, 0, &ci, &dec) : exr_decoding_initialize(ctx, 0, &ci, &dec);
        found = 0;
        for (int16_t k = 0; k < dec.channel_count && !rv; k++) {
            exr_coding_channel_info_t *ch = &dec.channels[k];
            const char *n = ch->channel_name;
            int c = !strcmp(n, "R") ? 0 : !strcmp(n, "G") ? 1 : !strcmp(n, "B") ? 2 : -1;
            ch->decode_to_ptr = NULL;
            if (c < 0)
                continue;
            found++;
            ch->decode_to_ptr = (uint8_t *)(out + ((size_t)(ci.start_y - dw.min.y) * *w) * 3 + c);
            ch->user_pixel_stride = 3 * sizeof(float);
            ch->user_line_stride = (int32_t)(3 * sizeof(float) * *w);
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = sizeof(float);
        }
        if (!rv && found != 3)
            rv = EXR_ERR_INVALID_ARGUMENT;
        if (!rv && !started) {
            started = 1;
            rv = exr_decoding_choose_default_routines(ctx, 0, &dec);
        }
        if (!rv)
            rv = exr_decoding_run(ctx, 0, &dec);
    }
    if (started)
        exr_decoding_destroy(ctx, &dec);
    exr_finish(&ctx);
    if (rv || !out) {
        free(out);
        return -1;
    }
    *rgb = out;
    return 0;
}
