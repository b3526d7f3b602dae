/* texture_jpeg_none.c - the JPEG reader of a build without libjpeg-turbo:
 * it only says so. */
#include "status.h"
#include "texture_internal.h"

int rt_texture_jpeg_decode(const uint8_t *data, size_t len, const rt_texture_limits *lim, rt_texture_image *out)
{
    (void)data;
    (void)len;
    (void)lim;
    *out = (rt_texture_image){0};
    return RT_ENOJPEG;
}
