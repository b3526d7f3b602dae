/* image.c - tone mapping of the accumulation buffer and the image hash. */
#include "image.h"

#include <math.h>

#include "render.h"
#include "hash.h"

static double mean(int64_t sum, uint32_t samples) { return ((double)sum / RT_FIX_ONE) / (double)samples; }

void rt_image_to_rgb8(const int64_t *acc, size_t n, uint32_t samples, uint8_t *rgb)
{
    for (size_t i = 0; i < 3 * n; i++) {
        double c = sqrt(mean(acc[i], samples));
        c = c < 0.0 ? 0.0 : c > 0.999 ? 0.999 : c;
        rgb[i] = (uint8_t)(256.0 * c);
    }
}

void rt_image_to_rgb16(const int64_t *acc, size_t n, uint32_t samples, uint16_t *rgb)
{
    for (size_t i = 0; i < 3 * n; i++) {
        double c = sqrt(mean(acc[i], samples));
        c = c < 0.0 ? 0.0 : c > 0.99999 ? 0.99999 : c;
        rgb[i] = (uint16_t)(65536.0 * c);
    }
}

void rt_image_to_linear(const int64_t *acc, size_t n, uint32_t samples, float *rgb)
{
    for (size_t i = 0; i < 3 * n; i++)
        rgb[i] = (float)mean(acc[i], samples);
}

void rt_image_extract(const int64_t *acc, size_t n, rt_layout lay, uint32_t first, uint32_t samples, int64_t *out)
{
    for (size_t i = 0; i < n; i++) {
        const int64_t *px = acc + i * lay.ch + first;
        const int64_t count = lay.count ? acc[i * lay.ch + lay.count] : (int64_t)samples;
        for (int k = 0; k < 3; k++) {
            if (count == (int64_t)samples) {
                out[3 * i + k] = px[k];
            } else if (count <= 0) {
                out[3 * i + k] = 0;
            } else {
                /* |sum| < 2^62 and samples <= 2^20: the product needs 128 bits */
                __int128 v = (__int128)px[k] * samples, h = count / 2;
                out[3 * i + k] = (int64_t)(v >= 0 ? (v + h) / count : -((-v + h) / count));
            }
        }
    }
}

uint64_t rt_image_hash(const uint8_t *bytes, size_t len) { return rt_hash_bytes(RT_HASH_INIT, bytes, len); }
