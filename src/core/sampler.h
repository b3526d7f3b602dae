/* sampler.h - the numbers a sample draws, keyed only by (seed, pixel, sample
 * index, dimension), so any sample of any pixel comes out the same on any
 * thread, rank, band or pass.
 *
 * Two samplers:
 * - RT_SAMPLER_RANDOM: the sample's splitmix64 stream (rng.h), drawn from in
 *   path order as the book does; sampling version 2's numbers, bit for bit.
 * - RT_SAMPLER_SOBOL: a padded, Owen-scrambled Sobol sampler. The dimensions
 *   come in pairs, each pair a 2D (0,2)-sequence (Sobol's first two
 *   dimensions) whose sample index is shuffled and whose coordinates are
 *   scrambled by hashes of (pixel key, pair): independent from pair to pair
 *   and pixel to pixel, and with no table to run out of, so a path may be
 *   any number of bounces deep. The index shuffle and the scrambles are
 *   nested (Owen) scrambles, so the first 2^k samples of a pixel (and every
 *   aligned block of 2^k) put exactly one point in each elementary interval
 *   of area 2^-k of every pair: a pixel stopped after 16, 32, 64, ...
 *   samples (adaptive sampling) is as well stratified as a full one.
 *
 * Layout of a Sobol sample's pairs: 0 the position in the pixel, 1 the lens,
 * then two per bounce: 2 + 2d the scattered direction at depth d, 3 + 2d a
 * material's third number (.x: a ball point's radius, the dielectric's
 * choice) and the Russian roulette (.y). Fixed slots, so a bounce's numbers
 * do not depend on which materials came before.
 *
 * All integer arithmetic and exact int->double conversions: the same bits
 * on every machine. */
#ifndef RT_SAMPLER_H
#define RT_SAMPLER_H

#include <stdint.h>
#include <string.h>

#include "rng.h"
#include "sample.h"
#include "vec.h"

typedef enum rt_sampler_kind {
    RT_SAMPLER_RANDOM = 0,
    RT_SAMPLER_SOBOL = 1,
} rt_sampler_kind;

/* "random", "sobol"; and back (-1 when unknown). */
static inline const char *rt_sampler_name(int kind)
{
    return kind == RT_SAMPLER_RANDOM ? "random" : kind == RT_SAMPLER_SOBOL ? "sobol" : "?";
}
static inline int rt_sampler_parse(const char *name)
{
    return !strcmp(name, "random") ? RT_SAMPLER_RANDOM : !strcmp(name, "sobol") ? RT_SAMPLER_SOBOL : -1;
}

/* Sample indices the Sobol sampler shuffles among: at least RT_MAX_SAMPLES
 * (render.h checks). */
#define RT_SAMPLER_INDEX_BITS 20

/* Pairs of the layout above. */
#define RT_SAMPLER_PAIR_PIXEL 0u
#define RT_SAMPLER_PAIR_LENS 1u
#define RT_SAMPLER_PAIR_BOUNCE 2u

typedef struct rt_sampler {
    rt_rng rng;         /* random: the sample's stream */
    uint64_t key;       /* sobol: the pixel's key (rt_rng_pixel_key) */
    uint32_t rev_index; /* sobol: the sample's index in its pixel, bit-reversed */
    uint32_t pair;      /* sobol: the current bounce's first pair */
    int kind;           /* rt_sampler_kind */
} rt_sampler;

/* ---- the Sobol pieces ----------------------------------------------------- */

static inline uint32_t rt_sampler_reverse(uint32_t x)
{
    x = __builtin_bswap32(x);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    return ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
}

/* A nested scramble of x's bits from the lowest up: bit b of the result is
 * bit b of x flipped by a function of seed and of x's bits below b. Every
 * step keeps that form (adding, multiplying by an odd number, xoring with a
 * multiple by an even number: carries only move upward), so whatever the
 * constants, the result is a bijection that maps each set of numbers equal
 * in their low k bits onto such a set. Applied to a bit-reversed fraction
 * it is an Owen scramble: each digit flipped by a hash of the digits above
 * it. The seed enters at three places so that no bit's flip is a plain
 * function of the seed's low bits. Measured against a true Owen scramble
 * (a 64-bit hash of the digits above, for every digit): the same error on
 * the final, materials and defocus scenes at 64 and 256 spp (within 5 %,
 * either way), at a twentieth of the cost. */
static inline uint32_t rt_sampler_nested(uint32_t x, uint32_t seed)
{
    x += seed;
    x ^= x * 0x3c6ef372u;
    x *= seed | 1u;
    x ^= x * 0xa54ff53au;
    x += seed >> 16 | seed << 16;
    x ^= x * 0x510e527eu;
    return x;
}

/* Sobol's second dimension of index i, bit-reversed. Its generator matrix
 * is Pascal's triangle mod 2 (primitive polynomial x + 1): index bit j
 * flips fraction digit k when the binomial C(j, k) is odd, which by Lucas'
 * theorem is when k's bits are a subset of j's. So digit k is the parity
 * of i's bits j that are supersets of k: a superset-sum transform over the
 * five bits of the position, five shifts. (The first dimension is the van
 * der Corput sequence: reversed, i itself.) */
static inline uint32_t rt_sampler_sobol1_reversed(uint32_t i)
{
    i ^= (i >> 1) & 0x55555555u;
    i ^= (i >> 2) & 0x33333333u;
    i ^= (i >> 4) & 0x0f0f0f0fu;
    i ^= (i >> 8) & 0x00ff00ffu;
    i ^= (i >> 16) & 0x0000ffffu;
    return i;
}

/* Hash of (pixel key, pair): the pair's index shuffle and scrambles. */
static inline uint64_t rt_sampler_pair_hash(uint64_t key, uint32_t pair)
{
    return rt_rng_mix(key ^ (((uint64_t)pair + 1) * UINT64_C(0x9fb21c651e98df25)));
}

/* The sample index (given bit-reversed) shuffled by a nested scramble of
 * its bits from the highest down, within [0, 2^INDEX_BITS): aligned blocks
 * of 2^k indices map onto aligned blocks, which the (0,2)-sequence fills as
 * nets. */
static inline uint32_t rt_sampler_shuffle(uint32_t rev_index, uint64_t h)
{
    return rt_sampler_reverse(rt_sampler_nested(rev_index, (uint32_t)h)) & ((1u << RT_SAMPLER_INDEX_BITS) - 1u);
}

/* Coordinate c of the pair's point for shuffled index s (hash h), Owen
 * scrambled, bit-reversed. Each coordinate's scramble seed comes from all
 * 64 bits of h. */
static inline uint32_t rt_sampler_coord_reversed(uint32_t s, uint64_t h, int c)
{
    if (!c)
        return rt_sampler_nested(s, (uint32_t)(h >> 32));
    uint32_t seed = (uint32_t)((h * UINT64_C(0xd1b54a32d192ed03)) >> 32);
    return rt_sampler_nested(rt_sampler_sobol1_reversed(s), seed);
}

/* Both halves of x reversed, and swapped: one reversal for a pair. */
static inline uint64_t rt_sampler_reverse64(uint64_t x)
{
    x = __builtin_bswap64(x);
    x = ((x >> 4) & UINT64_C(0x0f0f0f0f0f0f0f0f)) | ((x & UINT64_C(0x0f0f0f0f0f0f0f0f)) << 4);
    x = ((x >> 2) & UINT64_C(0x3333333333333333)) | ((x & UINT64_C(0x3333333333333333)) << 2);
    return ((x >> 1) & UINT64_C(0x5555555555555555)) | ((x & UINT64_C(0x5555555555555555)) << 1);
}

/* Coordinate c (0 or 1) of pair `pair` of sample `index` of the pixel whose
 * key is key, as a 32-bit fraction. */
static inline uint32_t rt_sampler_sobol_u32(uint64_t key, uint32_t index, uint32_t pair, int c)
{
    uint64_t h = rt_sampler_pair_hash(key, pair);
    return rt_sampler_reverse(rt_sampler_coord_reversed(rt_sampler_shuffle(rt_sampler_reverse(index), h), h, c));
}

/* A 32-bit fraction as a double in (0, 1): the middle of its interval. */
static inline double rt_sampler_unit(uint32_t v)
{
    return ((double)v + 0.5) * 0x1.0p-32;
}

/* ---- a sample's sampler ---------------------------------------------------- */

/* The sampler of sample `sample` of the pixel whose key is pixel_key. */
static inline rt_sampler rt_sampler_start(int kind, uint64_t pixel_key, uint32_t sample)
{
    rt_sampler s;
    s.rng.state = 0;
    if (kind == RT_SAMPLER_RANDOM)
        s.rng = rt_rng_for_pixel_sample(pixel_key, sample);
    s.key = pixel_key;
    s.rev_index = kind == RT_SAMPLER_RANDOM ? 0 : rt_sampler_reverse(sample);
    s.pair = RT_SAMPLER_PAIR_BOUNCE;
    s.kind = kind;
    return s;
}

/* A random sampler drawing from r (tests and tools). */
static inline rt_sampler rt_sampler_from_rng(rt_rng r)
{
    rt_sampler s = rt_sampler_start(RT_SAMPLER_RANDOM, 0, 0);
    s.rng = r;
    return s;
}

/* The next numbers are for the bounce at depth (where the segment at depth
 * ends). */
static inline void rt_sampler_bounce(rt_sampler *s, uint32_t depth)
{
    s->pair = RT_SAMPLER_PAIR_BOUNCE + 2u * depth;
}

static inline uint32_t sampler_coord(const rt_sampler *s, uint32_t pair, int c)
{
    uint64_t h = rt_sampler_pair_hash(s->key, pair);
    return rt_sampler_reverse(rt_sampler_coord_reversed(rt_sampler_shuffle(s->rev_index, h), h, c));
}

/* Both coordinates of a pair, as .x << 32 | .y (one hash, one shuffle and
 * one reversal for the two). */
static inline uint64_t sampler_pair64(const rt_sampler *s, uint32_t pair)
{
    uint64_t h = rt_sampler_pair_hash(s->key, pair);
    uint32_t i = rt_sampler_shuffle(s->rev_index, h);
    return rt_sampler_reverse64((uint64_t)rt_sampler_coord_reversed(i, h, 1) << 32 | rt_sampler_coord_reversed(i, h, 0));
}

static inline void sampler_pair(const rt_sampler *s, uint32_t pair, uint32_t *a, uint32_t *b)
{
    uint64_t v = sampler_pair64(s, pair);
    *a = (uint32_t)(v >> 32);
    *b = (uint32_t)v;
}

/* The position in the pixel, two numbers in [0, 1). */
static inline void rt_sampler_pixel(rt_sampler *s, double *du, double *dv)
{
    if (s->kind == RT_SAMPLER_RANDOM) {
        *du = rt_rng_double(&s->rng);
        *dv = rt_rng_double(&s->rng);
        return;
    }
    uint32_t a, b;
    sampler_pair(s, RT_SAMPLER_PAIR_PIXEL, &a, &b);
    *du = rt_sampler_unit(a);
    *dv = rt_sampler_unit(b);
}

/* A point in the unit disk (z = 0): for Sobol by polar coordinates, radius
 * sqrt(u), which keeps the pair's strata as equal-area sectors of rings. */
static inline rt_vec3 rt_sampler_disk(rt_sampler *s)
{
    if (s->kind == RT_SAMPLER_RANDOM)
        return rt_sample_in_unit_disk(&s->rng);
    uint32_t a, b;
    sampler_pair(s, RT_SAMPLER_PAIR_LENS, &a, &b);
    double r = sqrt(rt_sampler_unit(a)), c, sn;
    rt_sample_cos_sin_turn(b, &c, &sn);
    return rt_v3(r * c, r * sn, 0.0);
}

/* A uniform direction on the unit sphere: the bounce's first pair through
 * the same map as the random sampler's (rt_sample_unit_vector_bits). */
static inline rt_vec3 rt_sampler_unit_vector(rt_sampler *s)
{
    if (s->kind == RT_SAMPLER_RANDOM)
        return rt_sample_unit_vector(&s->rng);
    return rt_sample_unit_vector_bits(sampler_pair64(s, s->pair));
}

/* A uniform point inside the unit ball: for Sobol a direction (first pair)
 * at radius cbrt(u) (u: the second pair's .x). */
static inline rt_vec3 rt_sampler_in_unit_sphere(rt_sampler *s)
{
    if (s->kind == RT_SAMPLER_RANDOM)
        return rt_sample_in_unit_sphere(&s->rng);
    rt_vec3 d = rt_sampler_unit_vector(s);
    return rt_v3_scale(d, rt_sample_cbrt(rt_sampler_unit(sampler_coord(s, s->pair + 1u, 0))));
}

/* A uniform direction in the hemisphere around n. */
static inline rt_vec3 rt_sampler_in_hemisphere(rt_sampler *s, rt_vec3 n)
{
    if (s->kind == RT_SAMPLER_RANDOM)
        return rt_sample_in_hemisphere(&s->rng, n);
    rt_vec3 p = rt_sampler_unit_vector(s);
    return rt_v3_dot(p, n) > 0.0 ? p : rt_v3_neg(p);
}

/* A number in [0, 1) for a material's choice (the second pair's .x). */
static inline double rt_sampler_choice(rt_sampler *s)
{
    if (s->kind == RT_SAMPLER_RANDOM)
        return rt_rng_double(&s->rng);
    return rt_sampler_unit(sampler_coord(s, s->pair + 1u, 0));
}

/* A number in [0, 1) for the Russian roulette after this bounce (the
 * second pair's .y). */
static inline double rt_sampler_roulette(rt_sampler *s)
{
    if (s->kind == RT_SAMPLER_RANDOM)
        return rt_rng_double(&s->rng);
    return rt_sampler_unit(sampler_coord(s, s->pair + 1u, 1));
}

#endif
