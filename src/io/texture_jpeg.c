/* texture_jpeg.c - JPEG textures through libjpeg-turbo (libjpeg API). Every
 * libjpeg error and every warning (a cut file, corrupt entropy data: libjpeg
 * would fill in grey and go on) ends the read with a status; nothing is
 * printed. The size is checked from the header before anything is decoded,
 * and a progressive file may have at most MAX_SCANS scans (a file of many
 * tiny scans costs CPU without bound). */
#include <setjmp.h>
#include <stdio.h> /* before jpeglib.h, which needs FILE */
#include <stdlib.h>

#include <jerror.h>
#include <jpeglib.h>

#include "status.h"
#include "texture_internal.h"

/* libjpeg-turbo's own tools stop at 500 scans (TJFLAG_LIMITSCANS). */
#define MAX_SCANS 500

typedef struct jpeg_fail {
    struct jpeg_error_mgr mgr;
    jmp_buf jump;
    int status;
} jpeg_fail;

static int status_of(int code)
{
    switch (code) {
    case JWRN_JPEG_EOF:
    case JERR_INPUT_EOF:
    case JERR_INPUT_EMPTY:
        return RT_EIMAGE_TRUNCATED;
    case JERR_EMPTY_IMAGE:
        return RT_EIMAGE_EMPTY;
    case JERR_BAD_PRECISION:
        return RT_EIMAGE_DEPTH;
    case JERR_IMAGE_TOO_BIG:
        return RT_EOVERFLOW;
    case JERR_OUT_OF_MEMORY:
        return RT_ENOMEM;
    default:
        return RT_EIMAGE_CORRUPT;
    }
}

static void fail_now(j_common_ptr c, int status)
{
    jpeg_fail *f = (jpeg_fail *)c->err;
    f->status = status;
    longjmp(f->jump, 1);
}

static void on_error(j_common_ptr c) { fail_now(c, status_of(c->err->msg_code)); }

static void on_message(j_common_ptr c, int level)
{
    if (level < 0) /* a warning: the data is damaged */
        fail_now(c, status_of(c->err->msg_code));
}

static void on_progress(j_common_ptr c)
{
    j_decompress_ptr d = (j_decompress_ptr)c;
    if (d->progressive_mode && d->input_scan_number > MAX_SCANS)
        fail_now(c, RT_EIMAGE_LIMIT);
}

/* After the header: RT_OK when the image may be decoded as 8-bit RGB. */
static int check_header(j_decompress_ptr d, const rt_texture_limits *lim)
{
    if (d->jpeg_color_space == JCS_CMYK || d->jpeg_color_space == JCS_YCCK)
        return RT_EIMAGE_CMYK;
    if (d->num_components != 1 && d->num_components != 3)
        return RT_EIMAGE_CORRUPT;
    return rt_texture_check_size(d->image_width, d->image_height, lim);
}

int rt_texture_jpeg_decode(const uint8_t *data, size_t len, const rt_texture_limits *lim, rt_texture_image *out)
{
    struct jpeg_decompress_struct d;
    jpeg_fail f = {.status = RT_OK};
    struct jpeg_progress_mgr progress = {.progress_monitor = on_progress};
    d.err = jpeg_std_error(&f.mgr);
    f.mgr.error_exit = on_error;
    f.mgr.emit_message = on_message;
    if (setjmp(f.jump)) {
        jpeg_destroy_decompress(&d);
        rt_texture_image_free(out);
        return f.status;
    }
    jpeg_create_decompress(&d);
    d.progress = &progress;
    jpeg_mem_src(&d, data, (unsigned long)len);
    jpeg_read_header(&d, TRUE);
    int st = check_header(&d, lim);
    if (st == RT_OK) {
        d.out_color_space = JCS_RGB;
        jpeg_start_decompress(&d);
        if (d.output_components != 3 || d.output_width != d.image_width || d.output_height != d.image_height)
            st = RT_EIMAGE_CORRUPT;
    }
    if (st == RT_OK)
        st = rt_texture_alloc(out, d.output_width, d.output_height);
    if (st == RT_OK) {
        while (d.output_scanline < d.output_height) {
            JSAMPROW row = out->texels + (size_t)d.output_scanline * out->width * 3;
            jpeg_read_scanlines(&d, &row, 1);
        }
        jpeg_finish_decompress(&d);
    }
    jpeg_destroy_decompress(&d);
    if (st != RT_OK)
        rt_texture_image_free(out);
    return st;
}
