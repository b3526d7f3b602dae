/* texture_image.h - reads PNG and JPEG files for image textures, with limits
 * against hostile files. Rank 0 reads; the result is plain bytes that can
 * travel inside the scene's broadcast. No MPI, no printing. */
#ifndef RT_TEXTURE_IMAGE_H
#define RT_TEXTURE_IMAGE_H

#include <stddef.h>
#include <stdint.h>

#include "scene.h"

/* The default limits: the scene format's texels per image
 * (RT_SCENE_MAX_IMAGE_PIXELS); a file is refused before any texel is
 * decoded when its header announces more. */
#define RT_TEXTURE_MAX_PIXELS RT_SCENE_MAX_IMAGE_PIXELS
#define RT_TEXTURE_MAX_FILE_BYTES ((size_t)1 << 28)

typedef struct rt_texture_limits {
    uint64_t max_pixels;   /* width * height, checked from the header */
    size_t max_file_bytes; /* the file's size */
} rt_texture_limits;

/* width * height texels, 3 bytes each (R, G, B as stored in the file, i.e.
 * 8-bit sRGB-encoded), row-major from the top row. Alpha is dropped; 16-bit
 * PNG samples are scaled (rounded) to 8 bits; grey and palette become RGB.
 * width * height never exceeds UINT32_MAX (the scene's bytes index texels
 * with 32 bits). */
typedef struct rt_texture_image {
    uint32_t width, height;
    uint8_t *texels;
} rt_texture_image;

/* The default limits (RT_TEXTURE_MAX_PIXELS, RT_TEXTURE_MAX_FILE_BYTES). */
rt_texture_limits rt_texture_limits_default(void);

/* Reads the PNG or JPEG file at path (the type from its first bytes) into
 * *out; limits NULL means the defaults. On failure *out is empty and the
 * status is one of: RT_ENOFILE, RT_EIO, RT_EOVERFLOW (a file over
 * max_file_bytes, or width * height over UINT32_MAX), RT_ENOMEM,
 * RT_EIMAGE_TYPE, RT_EIMAGE_TRUNCATED, RT_EIMAGE_CORRUPT, RT_EIMAGE_CRC,
 * RT_EIMAGE_EMPTY (0 wide or high), RT_EIMAGE_LIMIT (over max_pixels),
 * RT_EIMAGE_CMYK, RT_EIMAGE_DEPTH, RT_ENOJPEG (a JPEG in a build without
 * libjpeg-turbo). */
int rt_texture_image_load(const char *path, const rt_texture_limits *limits, rt_texture_image *out);

/* The same from len bytes in memory (the fuzzer's entry point). */
int rt_texture_image_decode(const uint8_t *data, size_t len, const rt_texture_limits *limits, rt_texture_image *out);

void rt_texture_image_free(rt_texture_image *img);

#endif
