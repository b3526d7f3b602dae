/* sample.h - random directions and points drawn from an rt_rng stream, by
 * rejection so that only +,-,*,/ and sqrt are involved (bit-reproducible on
 * any IEEE-754 machine, independent of the libm). */
#ifndef RT_SAMPLE_H
#define RT_SAMPLE_H

#include "rng.h"
#include "vec.h"

/* Uniform point strictly inside the unit sphere. */
static inline rt_vec3 rt_sample_in_unit_sphere(rt_rng *r)
{
    for (;;) {
        double x = 2.0 * rt_rng_double(r) - 1.0;
        double y = 2.0 * rt_rng_double(r) - 1.0;
        double z = 2.0 * rt_rng_double(r) - 1.0;
        double l2 = x * x + y * y + z * z;
        if (l2 < 1.0 && l2 > 1e-30)
            return rt_v3(x, y, z);
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
        double x = 2.0 * rt_rng_double(r) - 1.0;
        double y = 2.0 * rt_rng_double(r) - 1.0;
        if (x * x + y * y < 1.0)
            return rt_v3(x, y, 0.0);
    }
}

#endif
