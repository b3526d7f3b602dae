/* fbox.h - the float boxes of the wide BVHs (the spheres' in bvh*.c, the
 * quads' and moving spheres' in world*.c): a box is stored in float rounded
 * outward, a ray's origin and inverse direction in float, and the interval
 * of a box test is a little wider than the double one, so that float
 * rounding never culls a box the exact ray enters. Private to those files. */
#ifndef RT_FBOX_H
#define RT_FBOX_H

#include <math.h>
#include <stdint.h>
#include <string.h>

/* 1 when f's sign bit is set (f < 0 for the nonzero values of safe_inv). */
static inline int sign_bit(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return (int)(u >> 31);
}

/* The float bounds of the box tests around the double interval (tmin,
 * closest): a little wider, so that a box the exact interval enters is never
 * culled by float rounding. INFINITY stays INFINITY. */
#define TMIN_SHRINK 0.999f
#define TFAR_GROW 1.0001f
static inline float near_bound(double tmin) { return (float)tmin * TMIN_SHRINK; }
static inline float far_bound(double closest) { return (float)closest * TFAR_GROW; }

/* 1 / d in float, never infinite: a zero component gives +-1e30. */
static inline float safe_inv(double d)
{
    float f = (float)d;
    if (fabsf(f) < 1e-30f)
        f = f < 0 ? -1e-30f : 1e-30f;
    return 1.0f / f;
}

/* v - margin and v + margin rounded outward to float. */
static inline float round_down(double v, double margin)
{
    float f = (float)(v - margin);
    return (double)f > v - margin ? nextafterf(f, -INFINITY) : f;
}
static inline float round_up(double v, double margin)
{
    float f = (float)(v + margin);
    return (double)f < v + margin ? nextafterf(f, INFINITY) : f;
}

#endif
