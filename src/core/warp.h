/* warp.h - numbers in [0, 1) to points: the maps a sampler's 2D and 1D
 * numbers (sampler.h) go through. A 2D number comes as two 32-bit
 * fractions, .x << 32 | .y; a 1D number as a double. Only +,-,*,/ and
 * sqrt: the same bits on every IEEE-754 machine (sample.h). Each keeps the
 * strata of its numbers as strata of equal measure (areas, solid angles),
 * so stratified numbers give stratified points. */
#ifndef RT_WARP_H
#define RT_WARP_H

#include <stdint.h>

#include "sample.h"
#include "vec.h"

/* A 32-bit fraction as a double in (0, 1): the middle of its interval. */
static inline double rt_warp_unit(uint32_t v)
{
    return ((double)v + 0.5) * 0x1.0p-32;
}

/* A point in the unit disk (z = 0) by polar coordinates: radius sqrt(.x),
 * angle .y turns; equal-area sectors of rings. */
static inline rt_vec3 rt_warp_disk(uint64_t u)
{
    double r = sqrt(rt_warp_unit((uint32_t)(u >> 32))), c, s;
    rt_sample_cos_sin_turn((uint32_t)u, &c, &s);
    return rt_v3(r * c, r * s, 0.0);
}

/* A uniform direction on the unit sphere (Archimedes: z from .x, azimuth
 * from .y). */
static inline rt_vec3 rt_warp_sphere(uint64_t u)
{
    return rt_sample_unit_vector_bits(u);
}

/* A uniform point inside the unit ball: a direction at radius cbrt(r). */
static inline rt_vec3 rt_warp_ball(uint64_t u, double r)
{
    return rt_v3_scale(rt_warp_sphere(u), rt_sample_cbrt(r));
}

/* The density, per unit solid angle, of the direction of m + f b for b
 * uniform in the unit ball (a fuzzy metal's reflection, material.c: m the
 * mirror direction, unit; f the fuzz, > 0), in unit direction w: the ball
 * of radius f about m as seen from the origin, (s2^3 - s1^3) / (4 pi f^3)
 * over the chord [s1, s2] that the ray along w cuts from it (s1 clamped at
 * 0 when the ball holds the origin, f >= 1). */
static inline double rt_warp_fuzz_pdf(rt_vec3 m, double f, rt_vec3 w)
{
    const double b = rt_v3_dot(w, m), disc = b * b - (rt_v3_len2(m) - f * f);
    if (!(disc > 0.0))
        return 0.0;
    const double q = sqrt(disc), s2 = b + q, s1 = b - q > 0.0 ? b - q : 0.0;
    if (!(s2 > 0.0))
        return 0.0;
    return (s2 * s2 * s2 - s1 * s1 * s1) / (4.0 * 3.14159265358979323846 * f * f * f);
}

/* A uniform direction in the hemisphere around n: the sphere's, flipped
 * to n's side. */
static inline rt_vec3 rt_warp_hemisphere(uint64_t u, rt_vec3 n)
{
    rt_vec3 p = rt_warp_sphere(u);
    return rt_v3_dot(p, n) > 0.0 ? p : rt_v3_neg(p);
}

/* A cosine-weighted direction around n (Lambert's law): n plus a uniform
 * direction, the book's construction; the zero vector when they cancel
 * (the caller takes n then). */
static inline rt_vec3 rt_warp_cosine(uint64_t u, rt_vec3 n)
{
    return rt_v3_add(n, rt_warp_sphere(u));
}

/* n plus the uniform direction s (rt_warp_sphere's), n itself when they
 * cancel: a lambertian bounce's direction. */
static inline rt_vec3 rt_warp_lambert_of(rt_vec3 s, rt_vec3 n)
{
    const rt_vec3 d = rt_v3_add(n, s);
    return rt_v3_near_zero(d) ? n : d;
}

/* The same from the 2D number u. */
static inline rt_vec3 rt_warp_lambert(uint64_t u, rt_vec3 n)
{
    return rt_warp_lambert_of(rt_warp_sphere(u), n);
}

#endif
