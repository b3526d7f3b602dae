/* detmath.h - the few transcendental functions book 2's scenes need per
 * sample (a medium's free-flight distance, the marble texture), in plain
 * IEEE arithmetic with no libm, so every node computes the same bits
 * whatever its libm or CPU (libm's variants differ with FMA). Accurate to
 * about 1e-15 relative (log) and 1e-11 (sin), checked in test_texture.c.
 * Header-only. */
#ifndef RT_DETMATH_H
#define RT_DETMATH_H

#include <stdint.h>
#include <string.h>

#include "sample.h"

/* ln(x) for finite x > 0 (0 and below: -inf; the caller never passes
 * those but for x = 0, whose -ln is +inf: no event). */
static inline double rt_det_log(double x)
{
    if (!(x > 0.0))
        return -1.0 / 0.0;
    uint64_t b;
    memcpy(&b, &x, 8);
    int e = (int)((b >> 52) & 0x7ff);
    if (e == 0) { /* subnormal: scale into the normal range */
        x *= 0x1p54;
        memcpy(&b, &x, 8);
        e = (int)((b >> 52) & 0x7ff) - 54;
    }
    e -= 1023;
    b = (b & UINT64_C(0x000fffffffffffff)) | UINT64_C(0x3ff0000000000000); /* m in [1, 2) */
    double m;
    memcpy(&m, &b, 8);
    if (m > 1.41421356237309504880) { /* m in [sqrt(1/2), sqrt(2)) */
        m *= 0.5;
        e++;
    }
    /* ln m = 2 atanh(s), s = (m - 1) / (m + 1), |s| < 0.172 */
    const double s = (m - 1.0) / (m + 1.0), s2 = s * s;
    double p = 1.0 / 25;
    for (int k = 23; k >= 1; k -= 2)
        p = 1.0 / k + s2 * p;
    return 2.0 * s * p + (double)e * 0.69314718055994530942;
}

/* sin(x) for |x| < 2^40: x in turns to 32 bits (an error of 2pi 2^-32
 * radians at most, far below what a texture shows), then
 * rt_sample_cos_sin_turn. */
static inline double rt_det_sin(double x)
{
    if (!(x > -0x1p40 && x < 0x1p40))
        return 0.0;
    const double turns = x * (4294967296.0 / 6.28318530717958647692);
    const int64_t q = (int64_t)turns - (turns < 0 && (double)(int64_t)turns != turns); /* floor */
    double c, s;
    rt_sample_cos_sin_turn((uint32_t)(uint64_t)q, &c, &s);
    return s;
}

#endif
