/* detmath.h - the few transcendental functions book 2's scenes need per
 * sample (a medium's free-flight distance and transmittance, the marble
 * texture, the equi-angular distance of path2.c's inscatter), in plain
 * IEEE arithmetic with no libm, so every node computes the same bits
 * whatever its libm or CPU (libm's variants differ with FMA). Accurate to
 * about 1e-15 relative (log, atan, 1 - exp(-x)), 1e-13 (exp(-x)), 1e-10
 * (tan near pi/2) and 1e-9 (sin), checked in test_world.c.
 * Header-only. */
#ifndef RT_DETMATH_H
#define RT_DETMATH_H

#include <stdint.h>
#include <string.h>

#include "sample.h"

/* 1 / k for k = 0..33 (0 for k = 0), each the division's correctly
 * rounded quotient: the series below take their coefficients from it
 * instead of dividing. */
static const double rt_det_inv[34] = {
    0, 1.0 / 1, 1.0 / 2, 1.0 / 3, 1.0 / 4, 1.0 / 5, 1.0 / 6, 1.0 / 7, 1.0 / 8, 1.0 / 9, 1.0 / 10, 1.0 / 11, 1.0 / 12,
    1.0 / 13, 1.0 / 14, 1.0 / 15, 1.0 / 16, 1.0 / 17, 1.0 / 18, 1.0 / 19, 1.0 / 20, 1.0 / 21, 1.0 / 22, 1.0 / 23,
    1.0 / 24, 1.0 / 25, 1.0 / 26, 1.0 / 27, 1.0 / 28, 1.0 / 29, 1.0 / 30, 1.0 / 31, 1.0 / 32, 1.0 / 33
};

/* 1 / k! for k = 0..19, the same way. */
static const double rt_det_inv_fact[20] = {
    1.0 / 1.0, 1.0 / 1.0, 1.0 / 2.0, 1.0 / 6.0, 1.0 / 24.0, 1.0 / 120.0, 1.0 / 720.0, 1.0 / 5040.0, 1.0 / 40320.0,
    1.0 / 362880.0, 1.0 / 3628800.0, 1.0 / 39916800.0, 1.0 / 479001600.0, 1.0 / 6227020800.0, 1.0 / 87178291200.0,
    1.0 / 1307674368000.0, 1.0 / 20922789888000.0, 1.0 / 355687428096000.0, 1.0 / 6402373705728000.0,
    1.0 / 121645100408832000.0
};

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
    double p = rt_det_inv[25];
    for (int k = 23; k >= 1; k -= 2)
        p = rt_det_inv[k] + s2 * p;
    return 2.0 * s * p + (double)e * 0.69314718055994530942;
}

/* exp(-x) for x >= 0: 2^-k e^-f with x = k ln 2 + f, f in [0, ln 2), a
 * Taylor series to below 1e-16; 0 past 700. No libm. */
static inline double rt_det_exp_neg(double x)
{
    if (!(x < 700.0))
        return 0.0;
    const double ln2 = 0.69314718055994530942;
    const int k = (int)(x / ln2);
    const double f = x - k * ln2;
    double sum = rt_det_inv_fact[17];
    for (int i = 16; i >= 0; i--)
        sum = rt_det_inv_fact[i] - f * sum;
    uint64_t b = (uint64_t)(1023 - k) << 52; /* 2^-k, k <= 1010 */
    double scale;
    memcpy(&scale, &b, 8);
    return sum * scale;
}

/* 1 - exp(-x) for x >= 0, without the cancellation of the difference
 * for small x (a thin medium's chance to scatter): its series below 0.5. */
static inline double rt_det_one_minus_exp_neg(double x)
{
    if (x > 0.5)
        return 1.0 - rt_det_exp_neg(x);
    double sum = rt_det_inv_fact[18];
    for (int i = 17; i >= 1; i--)
        sum = rt_det_inv_fact[i] - x * sum;
    return x * sum;
}

/* atan(x) for finite x: atan(|x|) = pi/2 - atan(1/|x|) past 1, and
 * pi/6 + atan((y sqrt 3 - 1) / (y + sqrt 3)) past tan(pi/12), which leaves
 * an argument of at most tan(pi/12) = 0.268 for the series; about 1e-16
 * relative. */
static inline double rt_det_atan(double x)
{
    const double pi = 3.14159265358979323846, r3 = 1.73205080756887729353;
    const double ax = x < 0 ? -x : x, y = ax > 1.0 ? 1.0 / ax : ax;
    const int big = y > 0.26794919243112270647;
    const double z = big ? (y * r3 - 1.0) / (y + r3) : y, z2 = z * z;
    double p = rt_det_inv[33];
    for (int k = 31; k >= 1; k -= 2)
        p = rt_det_inv[k] - z2 * p;
    double a = (big ? pi / 6 : 0.0) + z * p;
    if (ax > 1.0)
        a = pi / 2 - a;
    return x < 0 ? -a : a;
}

/* tan(x) for |x| < pi/2: sin and cos of h = x / 2 by their series (|h| <
 * pi/4, to h^19), then tan x = 2 sin h cos h / (cos^2 h - sin^2 h). */
static inline double rt_det_tan(double x)
{
    const double h = 0.5 * x, h2 = h * h;
    double sn = rt_det_inv_fact[19], cs = rt_det_inv_fact[18];
    for (int k = 17; k >= 1; k -= 2) {
        sn = rt_det_inv_fact[k] - h2 * sn;
        cs = rt_det_inv_fact[k - 1] - h2 * cs;
    }
    sn *= h;
    return 2.0 * sn * cs / (cs * cs - sn * sn);
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
