/* sample.h - random directions and points drawn from an rt_rng stream, by
 * rejection so that only +,-,*,/ and sqrt are involved (bit-reproducible on
 * any IEEE-754 machine, independent of the libm). */
#ifndef RT_SAMPLE_H
#define RT_SAMPLE_H

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

/* Uniform direction on the unit sphere. */
static inline rt_vec3 rt_sample_unit_vector(rt_rng *r) { return rt_v3_unit(rt_sample_in_unit_sphere(r)); }

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
