/* texture_image_check.c - see texture_image_check.h. */
#include "texture_image_check.h"

#include <string.h>

#include "status.h"
#include "texture_image.h"

const char *fuzz_texture_image_check(const uint8_t *data, size_t size)
{
    /* A small pixel limit keeps each input fast; the default's checks are
     * the same code. */
    rt_texture_limits lim = {1u << 20, (size_t)1 << 24};
    rt_texture_image a, b;
    int st = rt_texture_image_decode(data, size, &lim, &a);
    const char *bad = NULL;
    if (!strcmp(rt_status_str(st), "unknown error"))
        bad = "a status missing from the status table";
    else if (st != RT_OK && (a.texels || a.width || a.height))
        bad = "a failure left an image behind";
    else if (st == RT_OK && (!a.texels || !a.width || !a.height || (uint64_t)a.width * a.height > lim.max_pixels))
        bad = "an image that is empty or over the limit";
    if (bad || st != RT_OK) {
        rt_texture_image_free(&a);
        return bad;
    }
    unsigned sum = 0; /* every texel is read: ASan sees a short buffer */
    for (size_t i = 0; i < (size_t)a.width * a.height * 3; i++)
        sum += a.texels[i];
    (void)sum;
    if (rt_texture_image_decode(data, size, &lim, &b) != RT_OK || b.width != a.width || b.height != a.height ||
        memcmp(a.texels, b.texels, (size_t)a.width * a.height * 3))
        bad = "a second decode differs";
    rt_texture_image_free(&a);
    rt_texture_image_free(&b);
    return bad;
}
