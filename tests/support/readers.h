/* readers.h - test-only image readers built on the reference libraries
 * (libpng's own decoder at 16 bits, OpenEXR's C decoder), independent of
 * rt-mpi's writers, so tests compare what a real reader sees. */
#ifndef RT_TEST_READERS_H
#define RT_TEST_READERS_H

#include <stdint.h>

/* 8-bit RGB PNG; *rgb is malloc'd. 0 on success. */
int test_read_png8(const char *path, uint8_t **rgb, uint32_t *w, uint32_t *h);
/* 16-bit RGB PNG; *rgb is malloc'd host-order samples. 0 on success. */
int test_read_png16(const char *path, uint16_t **rgb, uint32_t *w, uint32_t *h);
/* Calls fn(arg, key, text) for each text chunk before the image data.
 * 0 on success. */
int test_read_png_text(const char *path, void (*fn)(void *arg, const char *key, const char *text), void *arg);
/* Float R, G, B of a scanline EXR, rows from the top; *rgb is malloc'd. */
int test_read_exr(const char *path, float **rgb, uint32_t *w, uint32_t *h);

#endif
