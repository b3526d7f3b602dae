/* test_texture_image.c - the image-texture reader (src/io/texture_image.c,
 * texture_jpeg.c): PNG and JPEG files written here with libpng and libjpeg
 * come back with their texels, and every hostile file is refused with its
 * own status and an empty result. */
#include <stdio.h> /* before jpeglib.h */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <jpeglib.h>
#include <png.h>
#include <zlib.h>

#include "check.h"
#include "status.h"
#include "texture_image.h"

typedef struct buf {
    uint8_t *p;
    size_t n;
} buf;

static void put(buf *b, const void *src, size_t n)
{
    b->p = realloc(b->p, b->n + n);
    if (n)
        memcpy(b->p + b->n, src, n);
    b->n += n;
}

static void png_put(png_structp png, png_bytep data, size_t n) { put(png_get_io_ptr(png), data, n); }
static void png_flush_none(png_structp png) { (void)png; }

/* A PNG of w x h from rows of rowbytes bytes each (in the given type). */
static buf png_encode(uint32_t w, uint32_t h, int color, int depth, int interlace, const uint8_t *pix, size_t rowbytes,
                      const png_color *palette, int n_palette)
{
    buf b = {0};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        fprintf(stderr, "libpng failed to write the test image\n");
        exit(1);
    }
    png_set_write_fn(png, &b, png_put, png_flush_none);
    png_set_IHDR(png, info, w, h, depth, color, interlace, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (palette)
        png_set_PLTE(png, info, palette, n_palette);
    png_write_info(png, info);
    if (depth == 16)
        png_set_swap(png); /* the test's samples are host-order uint16 */
    png_bytep rows[64];
    for (uint32_t y = 0; y < h; y++)
        rows[y] = (png_bytep)pix + y * rowbytes;
    png_write_image(png, rows);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return b;
}

/* A JPEG of w x h filled with one colour of n components in space cs. */
static buf jpeg_encode(int w, int h, int n, J_COLOR_SPACE cs, const uint8_t *colour)
{
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr err;
    c.err = jpeg_std_error(&err);
    jpeg_create_compress(&c);
    unsigned char *mem = NULL;
    unsigned long len = 0;
    jpeg_mem_dest(&c, &mem, &len);
    c.image_width = w;
    c.image_height = h;
    c.input_components = n;
    c.in_color_space = cs;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 100, TRUE);
    jpeg_start_compress(&c, TRUE);
    uint8_t row[64 * 4];
    for (int x = 0; x < w; x++)
        memcpy(row + x * n, colour, n);
    while (c.next_scanline < c.image_height) {
        JSAMPROW r = row;
        jpeg_write_scanlines(&c, &r, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    buf b = {0};
    put(&b, mem, len);
    free(mem);
    return b;
}

/* The offset of the first marker FF code in a JPEG's header, or 0. */
static size_t jpeg_marker(const buf *b, uint8_t code)
{
    for (size_t pos = 2; pos + 4 <= b->n && b->p[pos] == 0xff;) {
        if (b->p[pos + 1] == code)
            return pos;
        pos += 2 + ((size_t)b->p[pos + 2] << 8 | b->p[pos + 3]);
    }
    return 0;
}

static void be32_put(uint8_t *p, uint32_t v)
{
    p[0] = v >> 24;
    p[1] = v >> 16;
    p[2] = v >> 8;
    p[3] = v;
}

/* A PNG chunk with its length and CRC. */
static void chunk(buf *b, const char *type, const uint8_t *data, uint32_t n)
{
    uint8_t head[8], crc[4];
    be32_put(head, n);
    memcpy(head + 4, type, 4);
    put(b, head, 8);
    put(b, data, n);
    uLong c = crc32(crc32(0L, Z_NULL, 0), head + 4, 4);
    be32_put(crc, (uint32_t)(n ? crc32(c, data, n) : c)); /* crc32(c, NULL, 0) is 0, not c */
    put(b, crc, 4);
}

/* A PNG whose header announces w x h RGB, with one IDAT of the given bytes. */
static buf png_forged(uint32_t w, uint32_t h, const uint8_t *idat, uint32_t n_idat)
{
    buf b = {0};
    put(&b, "\x89PNG\r\n\x1a\n", 8);
    uint8_t ihdr[13] = {0, 0, 0, 0, 0, 0, 0, 0, 8, 2, 0, 0, 0};
    be32_put(ihdr, w);
    be32_put(ihdr + 4, h);
    chunk(&b, "IHDR", ihdr, 13);
    chunk(&b, "IDAT", idat, n_idat);
    chunk(&b, "IEND", NULL, 0);
    return b;
}

static int decode(const buf *b, size_t n, const rt_texture_limits *lim, rt_texture_image *img)
{
    return rt_texture_image_decode(b->p, n, lim, img);
}

/* The status of decoding, checking that a failure leaves nothing behind. */
static int refused(const buf *b, size_t n, const rt_texture_limits *lim)
{
    rt_texture_image img = {7, 7, (uint8_t *)&img};
    int st = decode(b, n, lim, &img);
    if (st != RT_OK)
        CHECK(img.width == 0 && img.height == 0 && img.texels == NULL);
    rt_texture_image_free(&img);
    return st;
}

static void test_png_good(void)
{
    uint8_t rgb[2 * 9] = {1, 2, 3, 40, 50, 60, 255, 0, 128, 7, 8, 9, 100, 110, 120, 0, 255, 17};
    buf b = png_encode(3, 2, PNG_COLOR_TYPE_RGB, 8, PNG_INTERLACE_NONE, rgb, 9, NULL, 0);
    rt_texture_image img;
    CHECK_EQ_INT(decode(&b, b.n, NULL, &img), RT_OK);
    CHECK_EQ_INT(img.width, 3);
    CHECK_EQ_INT(img.height, 2);
    CHECK(img.texels && !memcmp(img.texels, rgb, sizeof rgb));
    rt_texture_image_free(&img);
    /* The pixel limit is inclusive: 6 texels pass at 6 and fail at 5. */
    rt_texture_limits lim = {6, 1 << 20};
    CHECK_EQ_INT(decode(&b, b.n, &lim, &img), RT_OK);
    rt_texture_image_free(&img);
    lim.max_pixels = 5;
    CHECK_EQ_INT(refused(&b, b.n, &lim), RT_EIMAGE_LIMIT);
    free(b.p);

    /* 16-bit samples are scaled and rounded to 8 bits. */
    uint16_t deep[3] = {0xffff, 0x8080, 0x1234};
    b = png_encode(1, 1, PNG_COLOR_TYPE_RGB, 16, PNG_INTERLACE_NONE, (uint8_t *)deep, 6, NULL, 0);
    CHECK_EQ_INT(decode(&b, b.n, NULL, &img), RT_OK);
    CHECK_EQ_INT(img.texels[0], 255);
    CHECK_EQ_INT(img.texels[1], 128);
    CHECK_EQ_INT(img.texels[2], 18); /* 4660 / 257 = 18.1 */
    rt_texture_image_free(&img);
    free(b.p);

    /* Grey with alpha: grey replicated, alpha dropped. */
    uint8_t ga[4] = {77, 0, 200, 255};
    b = png_encode(2, 1, PNG_COLOR_TYPE_GRAY_ALPHA, 8, PNG_INTERLACE_NONE, ga, 4, NULL, 0);
    CHECK_EQ_INT(decode(&b, b.n, NULL, &img), RT_OK);
    uint8_t want_ga[6] = {77, 77, 77, 200, 200, 200};
    CHECK(img.texels && !memcmp(img.texels, want_ga, 6));
    rt_texture_image_free(&img);
    free(b.p);

    /* A 2-bit palette: indices 3, 0, 1, 2 packed in one byte. */
    png_color pal[4] = {{10, 20, 30}, {40, 50, 60}, {70, 80, 90}, {250, 251, 252}};
    uint8_t idx[1] = {0xc6};
    b = png_encode(4, 1, PNG_COLOR_TYPE_PALETTE, 2, PNG_INTERLACE_NONE, idx, 1, pal, 4);
    CHECK_EQ_INT(decode(&b, b.n, NULL, &img), RT_OK);
    uint8_t want_pal[12] = {250, 251, 252, 10, 20, 30, 40, 50, 60, 70, 80, 90};
    CHECK(img.texels && !memcmp(img.texels, want_pal, 12));
    rt_texture_image_free(&img);
    free(b.p);

    /* Interlaced (Adam7), 5 x 5 with every texel distinct. */
    uint8_t il[75];
    for (int i = 0; i < 75; i++)
        il[i] = (uint8_t)(i * 3 + 1);
    b = png_encode(5, 5, PNG_COLOR_TYPE_RGB, 8, PNG_INTERLACE_ADAM7, il, 15, NULL, 0);
    CHECK_EQ_INT(decode(&b, b.n, NULL, &img), RT_OK);
    CHECK(img.texels && !memcmp(img.texels, il, 75));
    rt_texture_image_free(&img);
    free(b.p);
}

static void test_png_hostile(void)
{
    uint8_t rgb[12] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    buf b = png_encode(2, 2, PNG_COLOR_TYPE_RGB, 8, PNG_INTERLACE_NONE, rgb, 6, NULL, 0);
    size_t cuts[] = {3, 8, 20, 33, b.n / 2, b.n - 1};
    for (size_t i = 0; i < sizeof cuts / sizeof *cuts; i++)
        CHECK_EQ_INT(refused(&b, cuts[i], NULL), RT_EIMAGE_TRUNCATED);
    /* One byte of the IDAT's data changed (its CRC no longer matches). */
    b.p[33 + 8] ^= 0x40;
    CHECK_EQ_INT(refused(&b, b.n, NULL), RT_EIMAGE_CRC);
    free(b.p);

    /* Valid chunks, garbage where the compressed rows should be. */
    uint8_t junk[16] = {0xde, 0xad, 0xbe, 0xef, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    b = png_forged(2, 2, junk, sizeof junk);
    CHECK_EQ_INT(refused(&b, b.n, NULL), RT_EIMAGE_CORRUPT);
    free(b.p);
    b = png_forged(0, 5, junk, sizeof junk);
    CHECK_EQ_INT(refused(&b, b.n, NULL), RT_EIMAGE_EMPTY);
    free(b.p);
    b = png_forged(5, 0, junk, sizeof junk);
    CHECK_EQ_INT(refused(&b, b.n, NULL), RT_EIMAGE_EMPTY);
    free(b.p);
    /* 65536 x 65536 = 2^32 texels: overflows the 32-bit texel index even
     * when the caller sets no pixel limit. */
    rt_texture_limits open_lim = {UINT64_MAX, 1 << 20};
    b = png_forged(65536, 65536, junk, sizeof junk);
    CHECK_EQ_INT(refused(&b, b.n, &open_lim), RT_EOVERFLOW);
    free(b.p);
    /* A 10000 x 10000 bomb: 16 bytes announce 10^8 texels. */
    b = png_forged(10000, 10000, junk, sizeof junk);
    CHECK_EQ_INT(refused(&b, b.n, NULL), RT_EIMAGE_LIMIT);
    free(b.p);

    buf t = {0};
    put(&t, "{\"camera\": {}}", 14);
    CHECK_EQ_INT(refused(&t, t.n, NULL), RT_EIMAGE_TYPE);
    CHECK_EQ_INT(refused(&t, 0, NULL), RT_EIMAGE_TYPE);
    free(t.p);
}

static void test_jpeg(void)
{
    uint8_t colour[3] = {200, 100, 50};
    buf b = jpeg_encode(16, 8, 3, JCS_RGB, colour);
    rt_texture_image img;
    CHECK_EQ_INT(decode(&b, b.n, NULL, &img), RT_OK);
    CHECK_EQ_INT(img.width, 16);
    CHECK_EQ_INT(img.height, 8);
    int worst = 0;
    for (int i = 0; img.texels && i < 16 * 8 * 3; i++) {
        int d = abs(img.texels[i] - colour[i % 3]);
        worst = d > worst ? d : worst;
    }
    CHECK(img.texels != NULL);
    CHECK_EQ_INT(worst <= 2, 1); /* quality 100: off by at most 2 */
    rt_texture_image_free(&img);
    rt_texture_limits lim = {16 * 8 - 1, 1 << 20};
    CHECK_EQ_INT(refused(&b, b.n, &lim), RT_EIMAGE_LIMIT);
    CHECK_EQ_INT(refused(&b, b.n / 2, NULL), RT_EIMAGE_TRUNCATED);
    CHECK_EQ_INT(refused(&b, 40, NULL), RT_EIMAGE_TRUNCATED);
    CHECK_EQ_INT(refused(&b, b.n - 2, NULL), RT_EIMAGE_TRUNCATED); /* no EOI */

    /* The frame header: FF C0, length, precision, height, width. */
    size_t sof = jpeg_marker(&b, 0xc0);
    CHECK(sof > 0);
    buf h = {0};
    put(&h, b.p, b.n);
    h.p[sof + 5] = h.p[sof + 6] = 0;
    CHECK_EQ_INT(refused(&h, h.n, NULL), RT_EIMAGE_EMPTY);
    memcpy(h.p, b.p, b.n);
    h.p[sof + 5] = h.p[sof + 7] = 0xea; /* 60000 x 60000 */
    h.p[sof + 6] = h.p[sof + 8] = 0x60;
    CHECK_EQ_INT(refused(&h, h.n, NULL), RT_EIMAGE_LIMIT);
    memcpy(h.p, b.p, b.n);
    h.p[sof + 4] = 12;
    CHECK_EQ_INT(refused(&h, h.n, NULL), RT_EIMAGE_DEPTH);
    memcpy(h.p, b.p, b.n);
    size_t dqt = jpeg_marker(&b, 0xdb);
    CHECK(dqt > 0);
    h.p[dqt + 2] = 0;
    h.p[dqt + 3] = 1; /* a marker length shorter than its own field */
    CHECK_EQ_INT(refused(&h, h.n, NULL), RT_EIMAGE_CORRUPT);
    free(h.p);
    free(b.p);

    uint8_t grey = 90;
    b = jpeg_encode(8, 8, 1, JCS_GRAYSCALE, &grey);
    CHECK_EQ_INT(decode(&b, b.n, NULL, &img), RT_OK);
    CHECK(img.texels && img.texels[0] == img.texels[1] && img.texels[1] == img.texels[2]);
    CHECK(img.texels && abs(img.texels[0] - 90) <= 1);
    rt_texture_image_free(&img);
    free(b.p);

    uint8_t cmyk[4] = {0, 50, 100, 0};
    b = jpeg_encode(8, 8, 4, JCS_CMYK, cmyk);
    CHECK_EQ_INT(refused(&b, b.n, NULL), RT_EIMAGE_CMYK);
    free(b.p);
}

static void test_files(void)
{
    char dir[] = "/tmp/test_texture_XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[64];
    snprintf(path, sizeof path, "%s/t.png", dir);
    uint8_t rgb[3] = {9, 8, 7};
    buf b = png_encode(1, 1, PNG_COLOR_TYPE_RGB, 8, PNG_INTERLACE_NONE, rgb, 3, NULL, 0);
    FILE *f = fopen(path, "wb");
    CHECK(f && fwrite(b.p, 1, b.n, f) == b.n);
    if (f)
        fclose(f);
    rt_texture_image img;
    CHECK_EQ_INT(rt_texture_image_load(path, NULL, &img), RT_OK);
    CHECK(img.texels && img.width == 1 && img.height == 1 && !memcmp(img.texels, rgb, 3));
    rt_texture_image_free(&img);
    rt_texture_limits lim = {1, b.n - 1};
    CHECK_EQ_INT(rt_texture_image_load(path, &lim, &img), RT_EOVERFLOW);
    CHECK(img.texels == NULL);
    unlink(path);
    CHECK_EQ_INT(rt_texture_image_load(path, NULL, &img), RT_ENOFILE);
    CHECK(img.texels == NULL);
    CHECK_EQ_INT(rt_texture_image_load(dir, NULL, &img), RT_EIO);
    rmdir(dir);
    free(b.p);
    /* Every new status has its own message. */
    CHECK(strcmp(rt_status_str(RT_EIMAGE_CRC), rt_status_str(RT_EIMAGE_CORRUPT)) != 0);
    CHECK(strcmp(rt_status_str(RT_ENOJPEG), "unknown error") != 0);
}

int main(void)
{
    test_png_good();
    test_png_hostile();
    test_jpeg();
    test_files();
    CHECK_DONE();
}
