/* texture_internal.h - what texture_image.c shares with its JPEG reader
 * (texture_jpeg.c, or texture_jpeg_none.c in a build without libjpeg). */
#ifndef RT_TEXTURE_INTERNAL_H
#define RT_TEXTURE_INTERNAL_H

#include "texture_image.h"

/* RT_OK when a width x height image may be decoded under lim: else
 * RT_EIMAGE_EMPTY, RT_EOVERFLOW (over UINT32_MAX texels) or RT_EIMAGE_LIMIT. */
int rt_texture_check_size(uint64_t width, uint64_t height, const rt_texture_limits *lim);

/* Allocates out's texels for width x height (already checked). */
int rt_texture_alloc(rt_texture_image *out, uint32_t width, uint32_t height);

/* Decodes a JPEG (data starts with FF D8) into *out; statuses as
 * rt_texture_image_decode's. */
int rt_texture_jpeg_decode(const uint8_t *data, size_t len, const rt_texture_limits *lim, rt_texture_image *out);

#endif
