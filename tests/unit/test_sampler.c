/* test_sampler.c - the Sobol sampler's points: Sobol's second dimension
 * against its recurrence, the stratification of every pair (the first 2^k
 * samples of a pixel, and a later aligned block, put one point in each
 * elementary interval of area 2^-k), and independence: across pixels, and
 * between the pairs of one pixel's samples (which the index shuffle
 * provides: without it the pairs of a pixel would share their strata). The laws of the directions drawn from the points are tested
 * in test_material.c, their mean through a render in test_furnace.c. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "sampler.h"

/* Sobol's second dimension from its direction numbers (primitive
 * polynomial x + 1: m_k = m_{k-1} ^ 2 m_{k-1}, m_1 = 1), the textbook way. */
static uint32_t sobol1_reference(uint32_t i)
{
    uint32_t x = 0, m = 1;
    for (int j = 0; j < 32; j++, m ^= m << 1)
        if (i >> j & 1)
            x ^= m << (31 - j);
    return x;
}

static void check_sobol1(void)
{
    int same = 1;
    uint32_t bad = 0;
    for (uint32_t i = 0; i < (1u << 16); i++) {
        uint32_t want = sobol1_reference(i), got = rt_sampler_sobol1(rt_sampler_reverse(i));
        if (want != got && same) {
            same = 0;
            bad = i;
        }
    }
    printf("Sobol dimension 2: %s for indices below 2^16\n", same ? "as the direction numbers give" : "WRONG");
    CHECK_EQ_INT(bad, 0);
    CHECK(same);
}

/* The points by table are the definition's (rt_sampler_point_of): pair 0
 * (rt_sampler_pair0) from the index, and any pair (rt_sampler_point) from
 * its first coordinate, for every number below 2^16 and for numbers with
 * all four bytes set. */
static void check_tables(void)
{
    uint32_t bad0 = 0, bad = 0, first0 = 0, first = 0;
    rt_rng r = rt_rng_for_stream(5, RT_STREAM_TEST);
    for (uint32_t k = 0; k < (1u << 17); k++) {
        const uint32_t i = k < (1u << 16) ? k : (uint32_t)rt_rng_next(&r);
        const uint64_t shift = rt_rng_next(&r);
        if (rt_sampler_pair0(i) != rt_sampler_point_of(rt_sampler_reverse(i), 0) && !bad0++)
            first0 = i;
        if (rt_sampler_point(i, shift) != rt_sampler_point_of(i, shift) && !bad++)
            first = i;
    }
    printf("by table: pair 0 differs for %u of 2^17 indices (first: %#x), a point for %u of 2^17 "
           "coordinates (first: %#x)\n", bad0, first0, bad, first);
    CHECK_EQ_INT(bad0, 0);
    CHECK_EQ_INT(bad, 0);
}

/* Coordinate c of pair `pair` of sample i of the pixel with key key. */
static uint32_t sobol_u32(uint64_t key, uint32_t i, uint32_t pair, int c)
{
    uint64_t v = rt_sampler_sobol_pair(key, rt_sampler_reverse(i), pair);
    return c ? (uint32_t)v : (uint32_t)(v >> 32);
}

/* Points [first, first + 2^k) of pair `pair` of the pixel with key key: one
 * in each elementary interval of area 2^-k, for all k + 1 shapes. Returns
 * the number of shapes where some interval is empty. */
static int net_failures(uint64_t key, uint32_t pair, uint32_t first, int k, int *cells)
{
    uint32_t n = 1u << k;
    int bad = 0;
    for (int a = 0; a <= k; a++) { /* 2^a columns x 2^(k-a) rows */
        memset(cells, 0, n * sizeof *cells);
        for (uint32_t i = first; i < first + n; i++) {
            uint64_t x = sobol_u32(key, i, pair, 0), y = sobol_u32(key, i, pair, 1);
            uint32_t col = (uint32_t)(x >> (32 - a)), row = (uint32_t)(y >> (32 - (k - a)));
            cells[col << (k - a) | row]++;
        }
        int ok = 1;
        for (uint32_t c = 0; c < n; c++)
            ok &= cells[c] == 1;
        bad += !ok;
    }
    return bad;
}

static void check_stratification(void)
{
    enum { K = 12 };
    int *cells = malloc(sizeof(int) << K);
    const uint32_t pairs[] = {0, 1, 2, 3, 9, 1000, 200001}; /* pixel, lens, bounces, far beyond any table */
    int worst = 0;
    long shapes = 0;
    for (uint64_t pixel = 0; pixel < 3; pixel++) {
        uint64_t key = rt_rng_pixel_key(42, pixel * 7919);
        for (size_t p = 0; p < sizeof pairs / sizeof pairs[0]; p++) {
            for (int k = 0; k <= K; k++) {
                int bad = net_failures(key, pairs[p], 0, k, cells);
                shapes += k + 1;
                if (bad)
                    printf("pixel %llu pair %u: first 2^%d samples miss an interval in %d shapes\n",
                           (unsigned long long)pixel, pairs[p], k, bad);
                worst += bad;
            }
            /* a later aligned block: samples 3 * 2^8 .. 4 * 2^8, and
             * 2^19 .. 2^19 + 2^10 (the top of the samples' range) */
            worst += net_failures(key, pairs[p], 3u << 8, 8, cells);
            worst += net_failures(key, pairs[p], 1u << 19, 10, cells);
            shapes += 9 + 11;
        }
    }
    printf("stratification: %ld shapes of elementary intervals checked, %d with an empty interval\n", shapes, worst);
    CHECK_EQ_INT(worst, 0);
    free(cells);
}

static double uni(uint32_t v) { return rt_warp_unit(v) - 0.5; }

/* The same sample and pair in neighbouring pixels: uncorrelated, and
 * uniform (mean 1/2) at every sample index. */
static void check_across_pixels(void)
{
    const long NPIX = 20000, NS = 8;
    double sxy = 0, sxx = 0, syy = 0, mean[8] = {0};
    for (long p = 0; p < NPIX; p++) {
        uint64_t k0 = rt_rng_pixel_key(5, (uint64_t)p), k1 = rt_rng_pixel_key(5, (uint64_t)p + 1);
        for (uint32_t i = 0; i < NS; i++) {
            double x = uni(sobol_u32(k0, i, 2, 0)), y = uni(sobol_u32(k1, i, 2, 0));
            sxy += x * y;
            sxx += x * x;
            syy += y * y;
            mean[i] += x;
        }
    }
    double r = sxy / sqrt(sxx * syy), n = (double)NPIX * NS;
    printf("neighbouring pixels: correlation %.5f (standard error %.5f)\n", r, 1 / sqrt(n));
    CHECK_NEAR(r, 0.0, 5 / sqrt(n));
    for (uint32_t i = 0; i < NS; i++) /* a uniform coordinate: standard deviation sqrt(1/12) */
        CHECK_NEAR(mean[i] / NPIX, 0.0, 5 * sqrt(1.0 / 12 / NPIX));
}

/* Within one pixel, over its first n samples: how often coordinate cp of
 * pair p and coordinate cq of pair q fall in the same half (their top
 * digits agree), as (2 f - 1)^2 averaged over pixels, with its standard
 * error (from the spread). Pairs that kept the index order of the sequence
 * (padding without the shuffle) agree always or never: 1. With the shuffle
 * (a nested random permutation of the index bits from the top), the two
 * samples that differ only in index bit 0 share their other bits, so an
 * index's top digit is bit 0 flipped by a random function of those: both
 * pairs' top digits are bit 0 plus independent coin flips per such couple
 * of samples, agreeing or not as n / 2 fair coins: 2 / n in expectation. */
static void within_pixel(uint32_t p, int cp, uint32_t q, int cq, uint32_t n, long npix, double *mean, double *se)
{
    double s = 0, s2 = 0;
    for (long px = 0; px < npix; px++) {
        uint64_t key = rt_rng_pixel_key(9, (uint64_t)px);
        int agree = 0;
        for (uint32_t i = 0; i < n; i++)
            agree += (sobol_u32(key, i, p, cp) >> 31) == (sobol_u32(key, i, q, cq) >> 31);
        double d = 2.0 * agree / n - 1, d2 = d * d;
        s += d2;
        s2 += d2 * d2;
    }
    *mean = s / npix;
    *se = sqrt((s2 / npix - *mean * *mean) / npix);
}

static void check_within_pixel(void)
{
    const uint32_t cases[][4] = {{0, 0, 2, 0}, {2, 0, 3, 1}, {2, 1, 4, 1}, {3, 0, 5, 0}, {4, 1, 1000, 0}};
    for (uint32_t n = 4; n <= 64; n *= 4) {
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
            double m, se;
            within_pixel(cases[c][0], (int)cases[c][1], cases[c][2], (int)cases[c][3], n, 4000, &m, &se);
            printf("pair %u.%c and %u.%c, %2u samples of a pixel: top digits agree (2f - 1)^2 = %.4f "
                   "(expected %.4f, standard error %.4f)\n",
                   cases[c][0], "xy"[cases[c][1]], cases[c][2], "xy"[cases[c][3]], n, m, 2.0 / n, se);
            CHECK_NEAR(m, 2.0 / n, 5 * se);
        }
    }
}

/* The interface's numbers are the definition's (rt_sampler_sobol_pair) at
 * the dimensions sampler.h's table gives: a pixel keeps its first pairs'
 * seeds and shifts (RT_SAMPLER_KEPT), the others are hashed per request,
 * and both must give the same points. Requests as a path makes them: the
 * position, the lens, then per bounce a 2D direction and two 1D numbers. */
static void check_interface(void)
{
    int bad = 0;
    long n = 0;
    for (uint64_t pixel = 0; pixel < 4; pixel++) {
        const uint64_t key = rt_rng_pixel_key(3, pixel);
        rt_sampler_pixel px;
        rt_sampler_for_pixel(&px, RT_SAMPLER_SOBOL, key);
        for (uint32_t i = 0; i < 64; i += 7) {
            const uint32_t rev = rt_sampler_reverse(i);
            rt_sampler s = rt_sampler_start(&px, i);
            double du, dv;
            rt_sampler_pixel2d(&s, &du, &dv);
            uint64_t want = rt_sampler_sobol_pair(key, rev, 0);
            bad += du != rt_warp_unit((uint32_t)(want >> 32)) || dv != rt_warp_unit((uint32_t)want);
            bad += rt_sampler_get2d(&s) != rt_sampler_sobol_pair(key, rev, RT_SAMPLER_DIM_LENS / 2);
            n += 2;
            for (uint32_t d = 0; d < 6; d++) {
                rt_sampler_bounce(&s, d);
                const uint32_t pair = (RT_SAMPLER_DIM_BOUNCE + RT_SAMPLER_BOUNCE_DIMS * d) / 2;
                want = rt_sampler_sobol_pair(key, rev, pair + 1);
                bad += rt_sampler_get2d(&s) != rt_sampler_sobol_pair(key, rev, pair);
                bad += rt_sampler_get1d(&s) != rt_warp_unit((uint32_t)(want >> 32));
                bad += rt_sampler_get1d(&s) != rt_warp_unit((uint32_t)want);
                n += 3;
            }
        }
    }
    printf("interface: %d of %ld requests differ from the pairs' definition\n", bad, n);
    CHECK_EQ_INT(bad, 0);
}

/* rt_sampler_peek2d: for Sobol, at each even dimension of the book-2
 * layout's bounces, the number the request there returns, the sampler
 * left as it was; for the random sampler, nothing (its numbers depend on
 * the draws before them). */
static void check_peek(void)
{
    int bad = 0, peeked = 0;
    const uint64_t key = rt_rng_pixel_key(9, 17);
    for (int kind = RT_SAMPLER_RANDOM; kind <= RT_SAMPLER_SOBOL; kind++) {
        rt_sampler_pixel px = {0};
        rt_sampler_for_pixel(&px, kind, key);
        for (uint32_t i = 0; i < 40; i += 3) {
            rt_sampler s = rt_sampler_start(&px, i);
            for (uint32_t dim = RT_SAMPLER2_DIM_BOUNCE; dim < 120; dim += 2) {
                const rt_sampler before = s;
                uint64_t u = 0;
                const int got = rt_sampler_peek2d(&s, dim, &u);
                rt_sampler b = before, a = s; /* s as it was: the same next number */
                bad += rt_sampler_get2d(&a) != rt_sampler_get2d(&b) || a.dim != b.dim;
                rt_sampler_seek(&s, dim);
                const uint64_t want = rt_sampler_get2d(&s);
                if (kind == RT_SAMPLER_RANDOM) {
                    bad += got != 0;
                    continue;
                }
                peeked++;
                bad += got != 1 || u != want;
            }
        }
    }
    printf("peek2d: %d wrong of %d Sobol numbers peeked and the random sampler's refusals\n", bad, peeked);
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(peeked, 14 * 57);
}

int main(void)
{
    check_peek();
    check_interface();
    check_sobol1();
    check_tables();
    check_stratification();
    check_across_pixels();
    check_within_pixel();
    CHECK_DONE();
}
