/* rng.h - counter-keyed random streams.
 *
 * Every random number the renderer draws comes from a stream keyed by
 * (seed, pixel, sample) or by (seed, purpose): never from per-thread or
 * per-rank state. A stream is a splitmix64 sequence whose starting state is a
 * hash of its key, so any sample of any pixel can be regenerated in any order,
 * on any thread or rank, and yields the same numbers. Only integer operations
 * and an exact int->double conversion are used: the bits are identical on
 * every IEEE-754 machine. */
#ifndef RT_RNG_H
#define RT_RNG_H

#include <stdint.h>

typedef struct rt_rng {
    uint64_t state;
} rt_rng;

/* Purposes that own a stream of their own, so the scene draw never shares
 * numbers with pixel sampling. */
enum { RT_STREAM_SCENE = 1, RT_STREAM_TEST = 2, RT_STREAM_PERLIN = 3 };

/* Stafford's "Mix13" finalizer as used by splitmix64: a bijection on 64 bits
 * with full avalanche. */
#define RT_RNG_MIX_A UINT64_C(0xbf58476d1ce4e5b9) /* rt_rng_mix's multipliers (path_lanes.c's too) */
#define RT_RNG_MIX_B UINT64_C(0x94d049bb133111eb)
static inline uint64_t rt_rng_mix(uint64_t z)
{
    z = (z ^ (z >> 30)) * RT_RNG_MIX_A;
    z = (z ^ (z >> 27)) * RT_RNG_MIX_B;
    return z ^ (z >> 31);
}

#define RT_RNG_GAMMA UINT64_C(0x9e3779b97f4a7c15)

/* The part of a sample's key shared by all samples of one pixel
 * (pixel = y * width + x in image space): the renderer computes it once
 * per pixel. */
static inline uint64_t rt_rng_pixel_key(uint64_t seed, uint64_t pixel)
{
    return rt_rng_mix(rt_rng_mix(seed ^ UINT64_C(0x243f6a8885a308d3)) ^ (pixel * RT_RNG_GAMMA));
}

/* Stream for one sample of the pixel whose key is pixel_key. */
static inline rt_rng rt_rng_for_pixel_sample(uint64_t pixel_key, uint64_t sample)
{
    rt_rng r = {rt_rng_mix(pixel_key ^ (sample * UINT64_C(0xd1b54a32d192ed03)) ^ UINT64_C(0x13198a2e03707344))};
    return r;
}

/* Stream for one sample of one pixel. */
static inline rt_rng rt_rng_for_sample(uint64_t seed, uint64_t pixel, uint64_t sample)
{
    return rt_rng_for_pixel_sample(rt_rng_pixel_key(seed, pixel), sample);
}

/* Stream for a named purpose (scene construction, tests). */
static inline rt_rng rt_rng_for_stream(uint64_t seed, uint64_t purpose)
{
    rt_rng r = {rt_rng_mix(rt_rng_mix(seed ^ UINT64_C(0xa4093822299f31d0)) ^ (purpose * RT_RNG_GAMMA))};
    return r;
}

static inline uint64_t rt_rng_next(rt_rng *r)
{
    r->state += RT_RNG_GAMMA;
    return rt_rng_mix(r->state);
}

/* Uniform double in [0, 1) with 53 random bits. */
static inline double rt_rng_double(rt_rng *r)
{
    return (double)(rt_rng_next(r) >> 11) * 0x1.0p-53;
}

/* Uniform double in [lo, hi). */
static inline double rt_rng_range(rt_rng *r, double lo, double hi)
{
    return lo + (hi - lo) * rt_rng_double(r);
}

#endif
