/* sampler.h - the numbers a sample draws: an interface of dimensions, keyed
 * only by (seed, pixel, sample index, dimension), so any sample of any
 * pixel comes out the same on any thread, rank, band or pass.
 *
 * A sample asks its sampler for numbers, one request after the other:
 * rt_sampler_pixel2d first (the position in the pixel), then
 * rt_sampler_get2d and rt_sampler_get1d as the path needs them (warp.h
 * turns them into points), and rt_sampler_bounce before each bounce's.
 * Which dimension a request gets follows from their order, laid down here
 * and nowhere else:
 *
 *   dimensions        request                      asked by
 *   0-1               2D the position in the pixel  path.h, path_start
 *   2-3               2D the lens (a camera with an aperture; else unused)
 *   4 + 4d ... 7 + 4d the bounce at depth d (rt_sampler_bounce(d)):
 *                     the material's numbers      material.c
 *                       lambertian: 2D direction
 *                       sphere/hemisphere diffuse, fuzzy metal: 2D
 *                         direction, 1D radius (ball)
 *                       dielectric: 1D reflect or refract
 *                     then 1D the Russian roulette path.h, path_roulette
 *
 * Scenes with book-2 content (world.h) are rendered by the book-2 path
 * loop (path2.c), whose layout is its own:
 *
 *   0-1               2D the position in the pixel  path2.c
 *   2-3               2D the lens
 *   4                 1D the ray's time in [0, 1) (motion blur)
 *   6 + 8d ...        the bounce at depth d (rt_sampler_seek):
 *     +0              1D the free flight in the media (an optical depth)
 *     +1              1D which medium scattered, when several overlap
 *     +2 ...          the material's or the medium's phase function's
 *                     numbers as above (isotropic: 2D direction), then 1D
 *                     the Russian roulette (at +4 or +5 at most)
 *   with light sampling (a scene with emitters, not --no-light-sampling),
 *   the bounce at depth d starts at 6 + 10d instead, and a diffuse vertex
 *   (lambertian, isotropic, fuzzy metal) draws before its scattering's
 *   numbers:
 *     +6              1D which light (nee.h, lights.h)
 *     +8 - +9         2D the direction toward it (a point of a quad, a
 *                     direction in a sphere's cone)
 *   (+7 unused: a 2D request takes an even dimension); in a lit scene
 *   with media a bounce takes 14 (from 6 + 14d), and a segment from the
 *   camera or a specular vertex through thin media draws its in-scattered
 *   light (path2.c, inscatter):
 *     +10             1D the distance along the segment
 *     +11             1D which light (its rest: whether, then the roulette)
 *     +12 - +13       2D the point on it; in a lit scene
 *   with glass spheres, a lambertian vertex's 2D direction (+2 - +3)
 *   also decides whether it aims at one of them (nee.h: its first
 *   fraction's eighth). The brute-force
 *   loop keeps 8 a bounce: its bytes, and those of scenes without
 *   emitters, are unchanged.
 *
 * A 2D request takes the next even dimension and the one after it, a 1D
 * request the next dimension. Each bounce starts at its own dimension, so
 * its numbers do not depend on the materials before it. A new feature
 * (a ray's time, a light's choice and a point on it, a distance in a
 * medium) adds its requests to this table, raises RT_SAMPLER_BOUNCE_DIMS
 * if a bounce needs more, and is a new sampling version (render.h).
 *
 * The kind is chosen once per job (rt_job.sampler); every request does the
 * same for every sample of the job:
 * - RT_SAMPLER_RANDOM: the sample's splitmix64 stream (rng.h), drawn from
 *   in request order as the book does, dimensions ignored: sampling
 *   version 2's numbers, bit for bit. Its ball and disk are the book's
 *   rejection draws (sample.h), whose count of numbers varies.
 * - RT_SAMPLER_SOBOL: padded Sobol points. Dimensions 2k and 2k + 1 are
 *   pair k, a 2D (0,2)-sequence (Sobol's first two dimensions) whose
 *   sample index is shuffled, and whose coordinates are shifted, by hashes
 *   of (pixel key, pair): independent from pair to pair and pixel to
 *   pixel, with no table to run out of. The shuffle is a nested (Owen)
 *   scramble of the index's bits from the highest down, so the first 2^k
 *   samples of a pixel (and every aligned block of 2^k) take an aligned
 *   block of the sequence, a (0,k,2)-net: exactly one point in each
 *   elementary interval of area 2^-k of every pair, and a pixel stopped
 *   after 16, 32, 64, ... samples (adaptive sampling) is as well
 *   stratified as a full one. The coordinates' random digital shifts keep
 *   that; each point is uniform.
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
#include "warp.h"

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

/* The table above. */
#define RT_SAMPLER_DIM_PIXEL 0u
#define RT_SAMPLER_DIM_LENS 2u
#define RT_SAMPLER_DIM_BOUNCE 4u
#define RT_SAMPLER_BOUNCE_DIMS 4u
/* The book-2 layout. */
#define RT_SAMPLER2_DIM_TIME 4u
#define RT_SAMPLER2_DIM_BOUNCE 6u
#define RT_SAMPLER2_BOUNCE_DIMS 8u
#define RT_SAMPLER2_FLIGHT 0u   /* offsets in a bounce */
#define RT_SAMPLER2_MEDIUM 1u
#define RT_SAMPLER2_SCATTER 2u
/* With light sampling (path2.c, nee.h) a bounce takes 10 dimensions: */
#define RT_SAMPLER2_LIT_BOUNCE_DIMS 10u
#define RT_SAMPLER2_LIGHT 6u /* 1D which light, then 2D (8-9) the point on it */
/* and in lit scenes with media, 14 (path2.c's in-scattering along a segment): */
#define RT_SAMPLER2_LIT_MEDIA_BOUNCE_DIMS 14u
#define RT_SAMPLER2_INSCATTER 10u /* 1D the distance, then 1D (11) which light, 2D (12-13) the point */
/* and in lit scenes with glass spheres (caustic.h), 14: */
#define RT_SAMPLER2_LIT_CAUSTIC_BOUNCE_DIMS 14u
#define RT_SAMPLER2_CAUSTIC 10u /* 1D which light, then 2D (12-13) the point on it */

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
 * in their low k bits onto such a set. Applied to a bit-reversed index it
 * shuffles the index from its highest bit down. Two multiplications, where
 * sampling version 3 had three: the same errors on the final, materials
 * and defocus scenes (docs/SAMPLING.md), and the within-pixel independence
 * test (test_sampler.c) passes. */
#define RT_SAMPLER_NESTED_A 0x3c6ef372u /* its constants (path_lanes.c's too) */
#define RT_SAMPLER_NESTED_B 0xa54ff53au
static inline uint32_t rt_sampler_nested(uint32_t x, uint32_t seed)
{
    x += seed;
    x ^= x * RT_SAMPLER_NESTED_A;
    x *= seed | 1u;
    x ^= x * RT_SAMPLER_NESTED_B;
    return x;
}

/* Sobol's second dimension as a 32-bit fraction, from the first's (the van
 * der Corput fraction v, the index bit-reversed). Its generator matrix is
 * Pascal's triangle mod 2 (primitive polynomial x + 1): index bit j flips
 * fraction digit k when C(j, k) is odd, which by Lucas' theorem is when k's
 * bits are a subset of j's. Counted from the fraction's lowest bit (bit
 * 31 - j of v is index bit j), bit m of the result is the parity of v's
 * bits m' whose bits are a subset of m's: a subset-sum transform over the
 * five bits of the position, five shifts, no reversal. */
static inline uint32_t rt_sampler_sobol1(uint32_t v)
{
    v ^= (v << 1) & 0xaaaaaaaau;
    v ^= (v << 2) & 0xccccccccu;
    v ^= (v << 4) & 0xf0f0f0f0u;
    v ^= (v << 8) & 0xff00ff00u;
    v ^= v << 16;
    return v;
}

/* Hash of (pixel key, pair): the pair's index shuffle and shifts. */
#define RT_SAMPLER_PAIR_STEP UINT64_C(0x9fb21c651e98df25) /* a pair's step of the key (path_lanes.c's too) */
#define RT_SAMPLER_SHIFT_MUL UINT64_C(0xd1b54a32d192ed03) /* the second shift's multiplier */
static inline uint64_t rt_sampler_pair_hash(uint64_t key, uint32_t pair)
{
    return rt_rng_mix(key ^ (((uint64_t)pair + 1) * RT_SAMPLER_PAIR_STEP));
}

/* The shuffle seed and the shifts of a pair, from its hash. */
static inline void rt_sampler_pair_keys(uint64_t key, uint32_t pair, uint32_t *seed, uint64_t *shift)
{
    const uint64_t h = rt_sampler_pair_hash(key, pair);
    *seed = (uint32_t)h;
    *shift = (h & UINT64_C(0xffffffff00000000)) | (h * RT_SAMPLER_SHIFT_MUL) >> 32;
}

/* A pair's point, .x << 32 | .y (32-bit fractions), for the sample whose
 * index, bit-reversed and shuffled (rt_sampler_nested with the pair's
 * seed; pair 0 keeps the index's order, the others are shuffled against
 * it), is v: v is the van der Corput fraction of the shuffled index, the
 * first coordinate with no reversal back; each coordinate then takes a
 * random digital shift (xor) of its own. The definition. */
static inline uint64_t rt_sampler_point_of(uint32_t v, uint64_t shift)
{
    return ((uint64_t)v << 32 | rt_sampler_sobol1(v)) ^ shift;
}

/* The same by table: the unshifted point is linear over GF(2) in v's
 * bits, so it is the xor of the points of v's four bytes, each from a
 * table of 256 (sampler.c): four loads and xors in place of the
 * transform's fifteen operations and the merge. */
extern const uint64_t rt_sampler_point_table[4][256];
static inline uint64_t rt_sampler_point(uint32_t v, uint64_t shift)
{
    const uint64_t(*t)[256] = rt_sampler_point_table;
    return t[0][v & 0xffu] ^ t[1][(v >> 8) & 0xffu] ^ t[2][(v >> 16) & 0xffu] ^ t[3][v >> 24] ^ shift;
}

/* Pair `pair` of the sample whose index, bit-reversed, is rev_index, of the
 * pixel whose key is key (the definition; rt_sampler_get2d keeps the first
 * pairs' seeds and shifts for a pixel's samples). */
static inline uint64_t rt_sampler_sobol_pair(uint64_t key, uint32_t rev_index, uint32_t pair)
{
    uint32_t seed;
    uint64_t shift;
    rt_sampler_pair_keys(key, pair, &seed, &shift);
    return rt_sampler_point_of(pair ? rt_sampler_nested(rev_index, seed) : rev_index, shift);
}

/* Pair 0 of sample `index` before its shift, by table: both its
 * coordinates are linear over GF(2) in the index's bits too (the
 * reversal, then rt_sampler_sobol1), so it is the xor of the points of
 * the index's bytes, from tables of their own (sampler.c). Its first
 * coordinate is the bit-reversed index, which the other pairs' shuffles
 * take: four loads and xors in place of a reversal, a transform and a
 * merge. */
extern const uint64_t rt_sampler_pair0_table[4][256];
static inline uint64_t rt_sampler_pair0(uint32_t index)
{
    const uint64_t(*t)[256] = rt_sampler_pair0_table;
    uint64_t p = t[0][index & 0xffu] ^ t[1][(index >> 8) & 0xffu];
    if (index >> 16) /* a pixel's first 65536 samples need no more */
        p ^= t[2][(index >> 16) & 0xffu] ^ t[3][index >> 24];
    return p;
}

/* ---- a pixel's sampler, a sample's sampler: the interface ----------------- */

/* Pairs whose seed and shift a pixel keeps for its samples: the position,
 * the lens, the first bounce's two and the second bounce's first. Each
 * costs a hash per pixel instead of one per sample. */
#define RT_SAMPLER_KEPT 5u

/* What a pixel's samples share: the kind, chosen once; the pixel's key;
 * for Sobol the kept pairs' seeds and shifts. */
typedef struct rt_sampler_pixel {
    int kind;     /* rt_sampler_kind */
    uint64_t key; /* rt_rng_pixel_key */
    uint32_t seed[RT_SAMPLER_KEPT];
    uint64_t shift[RT_SAMPLER_KEPT];
} rt_sampler_pixel;

typedef struct rt_sampler {
    union {                     /* by kind: a path keeps its sampler, keep it small */
        rt_rng rng;             /* random: the sample's stream */
        uint64_t point0;        /* sobol: pair 0 before its shift (rt_sampler_pair0) */
    };
    const rt_sampler_pixel *px; /* sobol: its pixel's */
    uint32_t rev_index;         /* sobol: the sample's index in its pixel, bit-reversed */
    uint32_t dim;               /* sobol: the next request's dimension */
    int kind;                   /* rt_sampler_kind */
} rt_sampler;

/* The sampler of the pixel whose key is key (rt_rng_pixel_key). */
static inline void rt_sampler_for_pixel(rt_sampler_pixel *px, int kind, uint64_t key)
{
    px->kind = kind;
    px->key = key;
    if (kind == RT_SAMPLER_SOBOL)
        for (uint32_t k = 0; k < RT_SAMPLER_KEPT; k++)
            rt_sampler_pair_keys(key, k, &px->seed[k], &px->shift[k]);
    else /* the random sampler keeps none: zeros, so that copies copy set bytes */
        for (uint32_t k = 0; k < RT_SAMPLER_KEPT; k++)
            px->seed[k] = 0, px->shift[k] = 0;
}

/* The sampler of sample `sample` of px's pixel (px must outlive it). */
static inline rt_sampler rt_sampler_start(const rt_sampler_pixel *px, uint32_t sample)
{
    rt_sampler s;
    if (px->kind == RT_SAMPLER_RANDOM) {
        s.rng = rt_rng_for_pixel_sample(px->key, sample);
        s.rev_index = 0;
    } else {
        s.point0 = rt_sampler_pair0(sample);
        s.rev_index = (uint32_t)(s.point0 >> 32);
    }
    s.px = px;
    s.dim = RT_SAMPLER_DIM_PIXEL;
    s.kind = px->kind;
    return s;
}

/* A random sampler drawing from r (tests and tools). */
static inline rt_sampler rt_sampler_from_rng(rt_rng r)
{
    rt_sampler s = {.rng = r, .kind = RT_SAMPLER_RANDOM};
    return s;
}

/* Pair `pair` of s's sample. */
static inline uint64_t rt_sampler_pair(const rt_sampler *s, uint32_t pair)
{
    if (pair == 0)
        return s->point0 ^ s->px->shift[0];
    if (pair < RT_SAMPLER_KEPT)
        return rt_sampler_point(rt_sampler_nested(s->rev_index, s->px->seed[pair]), s->px->shift[pair]);
    uint32_t seed;
    uint64_t shift;
    rt_sampler_pair_keys(s->px->key, pair, &seed, &shift);
    return rt_sampler_point(rt_sampler_nested(s->rev_index, seed), shift);
}

/* The next requests are the bounce's at depth (where the segment at depth
 * ends). */
static inline void rt_sampler_bounce(rt_sampler *s, uint32_t depth)
{
    s->dim = RT_SAMPLER_DIM_BOUNCE + RT_SAMPLER_BOUNCE_DIMS * depth;
}

/* The next request takes dimension dim (the book-2 layout's bounces);
 * the random sampler draws in request order and ignores it. */
static inline void rt_sampler_seek(rt_sampler *s, uint32_t dim)
{
    s->dim = dim;
}

/* The next 2D number: .x << 32 | .y, two 32-bit fractions (warp.h). */
static inline uint64_t rt_sampler_get2d(rt_sampler *s)
{
    if (s->kind == RT_SAMPLER_RANDOM)
        return rt_rng_next(&s->rng);
    const uint32_t pair = (s->dim + 1u) >> 1;
    s->dim = 2u * pair + 2u;
    return rt_sampler_pair(s, pair);
}

/* The 2D number a request at dimension dim (even) would return, without
 * drawing it, where that number is a function of the dimension alone
 * (Sobol: returns 1 and sets *u); the random sampler's depend on the draws
 * before them (returns 0). A caller that takes it seeks to dim + 2, as the
 * request would have. */
static inline int rt_sampler_peek2d(const rt_sampler *s, uint32_t dim, uint64_t *u)
{
    if (s->kind == RT_SAMPLER_RANDOM)
        return 0;
    *u = rt_sampler_pair(s, dim >> 1);
    return 1;
}

/* The first coordinate of pair `pair` of s's sample (its .x), without
 * Sobol's second dimension: what a 1D request at an even dimension needs. */
static inline uint32_t rt_sampler_first(const rt_sampler *s, uint32_t pair)
{
    if (pair < RT_SAMPLER_KEPT)
        return (pair ? rt_sampler_nested(s->rev_index, s->px->seed[pair]) : s->rev_index) ^
               (uint32_t)(s->px->shift[pair] >> 32);
    uint32_t seed;
    uint64_t shift;
    rt_sampler_pair_keys(s->px->key, pair, &seed, &shift);
    return rt_sampler_nested(s->rev_index, seed) ^ (uint32_t)(shift >> 32);
}

/* The next 1D number, in (0, 1) ([0, 1) for random). */
static inline double rt_sampler_get1d(rt_sampler *s)
{
    if (s->kind == RT_SAMPLER_RANDOM)
        return rt_rng_double(&s->rng);
    const uint32_t d = s->dim++;
    return rt_warp_unit(d & 1u ? (uint32_t)rt_sampler_pair(s, d >> 1) : rt_sampler_first(s, d >> 1));
}

/* The position in the pixel (the first request), two numbers in [0, 1). */
static inline void rt_sampler_pixel2d(rt_sampler *s, double *du, double *dv)
{
    if (s->kind == RT_SAMPLER_RANDOM) {
        *du = rt_rng_double(&s->rng);
        *dv = rt_rng_double(&s->rng);
        return;
    }
    s->dim = RT_SAMPLER_DIM_PIXEL + 2u;
    const uint64_t v = rt_sampler_pair(s, RT_SAMPLER_DIM_PIXEL / 2u);
    *du = rt_warp_unit((uint32_t)(v >> 32));
    *dv = rt_warp_unit((uint32_t)v);
}

/* A point in the unit disk (z = 0) for the lens, dimensions 2-3. */
static inline rt_vec3 rt_sampler_lens(rt_sampler *s)
{
    if (s->kind == RT_SAMPLER_RANDOM)
        return rt_sample_in_unit_disk(&s->rng);
    s->dim = RT_SAMPLER_DIM_LENS + 2u;
    return rt_warp_disk(rt_sampler_pair(s, RT_SAMPLER_DIM_LENS / 2u));
}

/* A uniform point inside the unit ball: a 2D direction and a 1D radius. */
static inline rt_vec3 rt_sampler_ball(rt_sampler *s)
{
    if (s->kind == RT_SAMPLER_RANDOM)
        return rt_sample_in_unit_sphere(&s->rng);
    const uint64_t u = rt_sampler_get2d(s);
    return rt_warp_ball(u, rt_sampler_get1d(s));
}

/* A uniform direction in the hemisphere around n: 2D (random: a ball point
 * flipped to n's side, the book's third model, not of unit length). */
static inline rt_vec3 rt_sampler_hemisphere(rt_sampler *s, rt_vec3 n)
{
    if (s->kind == RT_SAMPLER_RANDOM)
        return rt_sample_in_hemisphere(&s->rng, n);
    return rt_warp_hemisphere(rt_sampler_get2d(s), n);
}

#endif
