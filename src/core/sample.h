/* sample.h - random directions and points drawn from an rt_rng stream with
 * only +,-,*,/ and sqrt (bit-reproducible on any IEEE-754 machine,
 * independent of the libm): by rejection, or for unit vectors directly with
 * a polynomial cosine and sine. */
#ifndef RT_SAMPLE_H
#define RT_SAMPLE_H

#include <stdint.h>

#include "rng.h"
#include "vec.h"

/* Three coordinates in [-1, 1) from one 64-bit draw, 21 bits each: a
 * direction needs no more resolution than 2^-20, and one draw instead of
 * three is a large part of the cost of a diffuse bounce. Exact in double. */
static inline rt_vec3 rt_sample_cube(rt_rng *r)
{
    uint64_t v = rt_rng_next(r);
    const double k = 0x1.0p-20; /* 21-bit integer -> [0, 2) */
    return rt_v3((double)(v >> 43) * k - 1.0, (double)((v >> 22) & 0x1fffff) * k - 1.0,
                 (double)((v >> 1) & 0x1fffff) * k - 1.0);
}

/* Uniform point strictly inside the unit sphere (by rejection). */
static inline rt_vec3 rt_sample_in_unit_sphere(rt_rng *r)
{
    for (;;) {
        rt_vec3 p = rt_sample_cube(r);
        double l2 = p.x * p.x + p.y * p.y + p.z * p.z;
        if (l2 < 1.0 && l2 > 1e-30)
            return p;
    }
}

/* cos and sin of the angle 2*pi * q / 2^32. Integer arithmetic picks the
 * nearest quarter turn, so the polynomials only see |a| <= pi/4, where their
 * truncation error is below 1e-11; the quarter turn is then applied exactly
 * (products with 0 and +-1). No libm: the same bits on every machine. The
 * constants are named for path_lanes.c, which does the same in vector
 * code: the radians of a 2^-32 turn, the quarter turns' cos and sin, and
 * the polynomials' coefficients in Horner order, innermost first (sin a =
 * a (1 - a^2/6 + ...), cos a = 1 - a^2/2 + ...). */
#define RT_SAMPLE_TURN_RADIANS (6.28318530717958647692 / 4294967296.0)
#define RT_SAMPLE_QUARTER_COS {1, 0, -1, 0}
#define RT_SAMPLE_QUARTER_SIN {0, 1, 0, -1}
#define RT_SAMPLE_SIN_POLY {-1.0 / 39916800, 1.0 / 362880, -1.0 / 5040, 1.0 / 120, -1.0 / 6, 1.0}
#define RT_SAMPLE_COS_POLY {1.0 / 479001600, -1.0 / 3628800, 1.0 / 40320, -1.0 / 720, 1.0 / 24, -1.0 / 2, 1.0}
static inline void rt_sample_cos_sin_turn(uint32_t q, double *c, double *s)
{
    static const double quarter_cos[4] = RT_SAMPLE_QUARTER_COS, quarter_sin[4] = RT_SAMPLE_QUARTER_SIN;
    static const double ks[6] = RT_SAMPLE_SIN_POLY, kc[7] = RT_SAMPLE_COS_POLY;
    uint32_t quarter = (q + 0x20000000u) >> 30;  /* round(q / 2^30) mod 4 */
    int32_t rest = (int32_t)(q - (quarter << 30)); /* in [-2^29, 2^29) */
    double a = (double)rest * RT_SAMPLE_TURN_RADIANS;
    double a2 = a * a, ps = ks[0], pc = kc[0];
    for (int i = 1; i < 6; i++)
        ps = ks[i] + a2 * ps;
    for (int i = 1; i < 7; i++)
        pc = kc[i] + a2 * pc;
    double sa = a * ps, ca = pc;
    *c = ca * quarter_cos[quarter] - sa * quarter_sin[quarter];
    *s = sa * quarter_cos[quarter] + ca * quarter_sin[quarter];
}

/* Uniform direction on the unit sphere, from 64 random bits and without
 * rejection (Archimedes: z uniform in (-1, 1), azimuth uniform). This is on
 * every diffuse bounce: against normalising a rejection-sampled point it
 * saves about one draw, an unpredictable branch and a division, about 10 %
 * of the final scene's render time. */
static inline rt_vec3 rt_sample_unit_vector_bits(uint64_t v)
{
    /* odd multiples of 2^-32 in (-1, 1), symmetric about 0 */
    double z = (double)(v >> 32) * 0x1.0p-31 - 1.0 + 0x1.0p-32;
    double rho = sqrt((1.0 - z) * (1.0 + z));
    double c, s;
    rt_sample_cos_sin_turn((uint32_t)v, &c, &s);
    return rt_v3(rho * c, rho * s, z);
}

/* The same from the next draw of r. */
static inline rt_vec3 rt_sample_unit_vector(rt_rng *r)
{
    return rt_sample_unit_vector_bits(rt_rng_next(r));
}

/* Cube root of u in [0, 1] without libm: a first guess from the exponent
 * (exact integer work on the bits), then Newton steps, each exact IEEE
 * arithmetic, so the same bits everywhere. Five steps from a guess within
 * a factor 2^(1/3) reach full precision (checked in test_sample.c). */
static inline double rt_sample_cbrt(double u)
{
    if (!(u > 0.0))
        return 0.0;
    int e = 0;
    double m = u;
    while (m < 0.125) { /* u = m * 8^-e, m in [1/8, 1] */
        m *= 8.0;
        e++;
    }
    double y = 0.5 + 0.5 * m; /* cbrt on [1/8, 1] lies in [1/2, 1] */
    for (int k = 0; k < 6; k++)
        y = (2.0 * y + m / (y * y)) * (1.0 / 3.0);
    for (; e > 0; e--)
        y *= 0.5;
    return y;
}

/* Uniform point in the hemisphere around n (seed 002's third model). */
static inline rt_vec3 rt_sample_in_hemisphere(rt_rng *r, rt_vec3 n)
{
    rt_vec3 p = rt_sample_in_unit_sphere(r);
    return rt_v3_dot(p, n) > 0.0 ? p : rt_v3_neg(p);
}

/* Uniform point in the unit disk z = 0. */
static inline rt_vec3 rt_sample_in_unit_disk(rt_rng *r)
{
    for (;;) {
        rt_vec3 p = rt_sample_cube(r);
        if (p.x * p.x + p.y * p.y < 1.0)
            return rt_v3(p.x, p.y, 0.0);
    }
}

#endif
