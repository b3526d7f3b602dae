/* test_adaptive.c - adaptive sampling (--noise-threshold):
 * - the count rule on pilots of known spread;
 * - every pixel of a small final scene, replayed sample by sample
 *   (rt_render_sample): its count is its pilot's (rt_render_pilot) and one
 *   of 16, 32, 64, ..., -s, its sums are exactly those of its first count
 *   samples, and rendering the samples in two ranges (as split units or
 *   progressive passes do) adds up to the same sums and count;
 * - no bias: the furnace (a lambertian sphere of albedo a under a white
 *   sky, roulette from the first bounce) comes out a within 5 standard
 *   errors for each sampler, with and without roulette; the final scene's
 *   channel means match a random-sampler reference within 5 standard
 *   errors; and once with power (check_bias_power): enough pixels that
 *   +1 % is over 10 standard errors, where pixels stop at different counts
 *   (in the furnaces without roulette every pixel stops at 16). (The first rule
 *   tried, stopping a pixel by its own samples at 16, 32, 64, ..., was
 *   1.3 % too bright here with the random sampler: the pilot's numbers are
 *   independent of the samples it counts.) */
#include <stdlib.h>
#include <string.h>

#include "accel.h"
#include "check.h"
#include "core_internal.h"
#include "furnace.h"
#include "render.h"
#include "status.h"

static void check_rule(void)
{
    /* no spread: the fewest samples */
    CHECK_EQ_INT(rt_render_adapt_count(16 * 0.5, 16 * 0.25, 16, 0.01, 1024), 16);
    /* 8 zeros and 8 ones: mean 0.5, variance 16/15 x 0.25 = 0.2667; the
     * mean of m samples is within 0.1 x 0.5 for m >= 106.7: 128 */
    CHECK_EQ_INT(rt_render_adapt_count(8, 8, 16, 0.1, 1024), 128);
    CHECK_EQ_INT(rt_render_adapt_count(8, 8, 16, 0.1, 100), 100); /* at most -s */
    CHECK_EQ_INT(rt_render_adapt_count(8, 8, 16, 0.2, 1024), 32); /* 26.7 */
    /* a dark pixel (mean 0.005) is held to RT_ADAPT_FLOOR instead: 0.01
     * and 0 alternating, variance 2.667e-5: m >= 2.667e-5 / (0.1 x 0.05)^2
     * = 1.07: 16 (with the mean itself as the reference it would be 1067) */
    CHECK_EQ_INT(rt_render_adapt_count(0.08, 8 * 1e-4, 16, 0.1, 4096), 16);
    CHECK_EQ_INT(rt_render_adapt_count(0.08, 8 * 1e-4, 16, 0.01, 4096), 128); /* 106.7 */
}

static void check_replay(void)
{
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_final(&s, 5, 2), RT_OK);
    rt_accel *a;
    CHECK_EQ_INT(rt_accel_new(&a, &s, RT_ACCEL_BVH), RT_OK);
    for (int kind = 0; kind < 2; kind++) {
        rt_job p = {24, 16, 128, 50, 7, RT_DIFFUSE_LAMBERTIAN, (rt_sampler_kind)kind, 1, 0, 0.03, 0, RT_LIGHT_MIS};
        rt_renderer r;
        CHECK_EQ_INT(rt_render_init(&r, &s, a, &p), RT_OK);
        CHECK_EQ_INT(r.lay.ch, 4);
        CHECK_EQ_INT(r.lay.count, 3);
        const size_t npix = (size_t)p.width * p.height, len = npix * r.lay.ch;
        int64_t *acc = calloc(len, sizeof *acc), *split = calloc(len, sizeof *split);
        rt_render_rows(&r, 0, p.height, 0, p.samples, acc, 2);
        rt_render_rows(&r, 0, p.height, 0, 40, split, 2);
        rt_render_rows(&r, 0, p.height, 40, p.samples, split, 1);
        unsigned early = 0, full = 0, bad_sums = 0, bad_count = 0;
        for (uint32_t y = 0; y < p.height; y++)
            for (uint32_t x = 0; x < p.width; x++) {
                const int64_t *px = acc + ((size_t)y * p.width + x) * r.lay.ch;
                const uint32_t n = (uint32_t)px[3];
                uint64_t segs = 0;
                int level = n == p.samples;
                for (uint32_t c = RT_ADAPT_FIRST; c < p.samples; c *= 2)
                    level |= n == c;
                bad_count += !level || n != rt_render_pilot(&r, x, y, &segs);
                early += n < p.samples;
                full += n == p.samples;
                int64_t sum[3] = {0, 0, 0};
                for (uint32_t k = 0; k < n; k++) {
                    rt_vec3 c = rt_render_sample(&r, x, y, k, &segs);
                    sum[0] += rt_render_fix(c.x), sum[1] += rt_render_fix(c.y), sum[2] += rt_render_fix(c.z);
                }
                bad_sums += memcmp(sum, px, sizeof sum) != 0;
            }
        printf("%s: %u pixels took fewer samples, %u all %u\n", rt_sampler_name(p.sampler), early, full, p.samples);
        CHECK_EQ_INT(bad_count, 0); /* the pilot's count, one of the fixed ones */
        CHECK_EQ_INT(bad_sums, 0);  /* the sums are the first n samples' */
        CHECK(early > 0 && full > 0); /* both happen in this image: the checks above mean something */
        CHECK(!memcmp(acc, split, len * sizeof *acc)); /* two sample ranges add up to the same */
        free(acc);
        free(split);
    }
    rt_accel_free(a);
    rt_scene_free(&s);
}

static void check_furnace(void)
{
    const rt_vec3 albedo = furnace_albedo();
    rt_scene s;
    rt_accel *a;
    furnace_scene(&s, &a);
    const double want[3] = {albedo.x, albedo.y, albedo.z};
    for (int kind = 0; kind < 2; kind++)
        for (int roulette = 0; roulette < 2; roulette++) {
            rt_job p = {32, 24, 256, 50, 3, RT_DIFFUSE_LAMBERTIAN, (rt_sampler_kind)kind, roulette, 1, 0.05, 0, RT_LIGHT_MIS};
            rt_renderer r;
            CHECK_EQ_INT(rt_render_init(&r, &s, a, &p), RT_OK);
            const size_t npix = (size_t)p.width * p.height;
            int64_t *acc = calloc(npix * r.lay.ch, sizeof *acc);
            rt_render_rows(&r, 0, p.height, 0, p.samples, acc, 2);
            /* the mean of the pixels' means, and its standard error from
             * their spread */
            double m[3] = {0}, m2[3] = {0}, spp = 0;
            for (size_t i = 0; i < npix; i++) {
                const int64_t *px = acc + i * r.lay.ch;
                spp += (double)px[3] / npix;
                for (int k = 0; k < 3; k++) {
                    double v = (double)px[k] / RT_FIX_ONE / (double)px[3];
                    m[k] += v / npix, m2[k] += v * v / npix;
                }
            }
            printf("furnace, adaptive %s%s: %.1f spp;", rt_sampler_name(p.sampler), roulette ? "+roulette" : "",
                   spp);
            for (int k = 0; k < 3; k++) {
                double se = sqrt((m2[k] - m[k] * m[k] > 0 ? m2[k] - m[k] * m[k] : 0) / npix);
                printf(" %.6f +- %.6f (want %.2f, off %+.2f%%)", m[k], se, want[k], 100 * (m[k] / want[k] - 1));
                /* 1e-9: the rounding of a to 2^-32 where every sample is a */
                CHECK_NEAR(m[k], want[k], 5 * se + 1e-9);
            }
            printf("\n");
            free(acc);
        }
    rt_accel_free(a);
    rt_scene_free(&s);
}

/* A test with power: the furnace with the random sampler and the roulette
 * from the first bounce (pixels stop at different counts: the check below
 * makes sure), at 128 x 96 pixels, so that the standard error of the
 * image's mean is under a tenth of 1 % of the albedo: a bias of +1 % is more
 * than 10 standard errors, far outside the 5 allowed. (A pilot that reused
 * the pixel's own numbers was +1.7 % here.) */
static void check_bias_power(void)
{
    const rt_vec3 albedo = furnace_albedo();
    rt_scene s;
    rt_accel *a;
    furnace_scene(&s, &a);
    rt_job p = {128, 96, 256, 50, 5, RT_DIFFUSE_LAMBERTIAN, RT_SAMPLER_RANDOM, 1, 1, 0.05, 0, RT_LIGHT_MIS};
    rt_renderer r;
    CHECK_EQ_INT(rt_render_init(&r, &s, a, &p), RT_OK);
    const size_t npix = (size_t)p.width * p.height;
    int64_t *acc = calloc(npix * r.lay.ch, sizeof *acc);
    rt_render_rows(&r, 0, p.height, 0, p.samples, acc, 2);
    /* red: the pixels' means, their mean and its standard error; how many
     * pixels took each count */
    double m = 0, m2 = 0;
    uint32_t by_count[9] = {0}; /* 16 << k samples */
    for (size_t i = 0; i < npix; i++) {
        const int64_t *px = acc + i * r.lay.ch;
        const double v = (double)px[0] / RT_FIX_ONE / (double)px[3];
        m += v / npix, m2 += v * v / npix;
        for (uint32_t k = 0; k < 9; k++)
            by_count[k] += (uint32_t)px[3] == (uint32_t)RT_ADAPT_FIRST << k;
    }
    const double se = sqrt((m2 - m * m > 0 ? m2 - m * m : 0) / npix);
    uint32_t levels = 0;
    printf("furnace with power, random+roulette, %zu pixels: red %.6f +- %.6f (want %.2f, off %+.3f%%, %.1f standard "
           "errors; +1%% would be %.1f); pixels by count:",
           npix, m, se, albedo.x, 100 * (m / albedo.x - 1), (m - albedo.x) / se, 0.01 * albedo.x / se);
    for (uint32_t k = 0; k < 9; k++) {
        if (by_count[k])
            printf(" %u: %u", RT_ADAPT_FIRST << k, by_count[k]);
        levels += by_count[k] >= npix / 10;
    }
    printf("\n");
    CHECK(levels >= 2);                  /* pixels stop at different counts */
    CHECK(0.01 * albedo.x >= 10 * se);   /* the power: +1 % is 10 standard errors or more */
    CHECK_NEAR(m, albedo.x, 5 * se);     /* no bias */
    free(acc);
    rt_accel_free(a);
    rt_scene_free(&s);
}

/* The final scene's channel means with adaptive sampling against a
 * reference of the random sampler at 1024 spp: each pixel's mean over its
 * own count, the image's mean of those, its standard error from every
 * pixel's sample spread over its count. */
static void check_final_means(void)
{
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_final(&s, 5, 2), RT_OK);
    rt_accel *a;
    CHECK_EQ_INT(rt_accel_new(&a, &s, RT_ACCEL_BVH), RT_OK);
    const uint32_t W = 24, H = 16;
    double mean[2][3] = {{0}}, var[2][3] = {{0}};
    for (int c = 0; c < 2; c++) {
        rt_job p = {W, H, c ? 256 : 1024, 50, 12, RT_DIFFUSE_LAMBERTIAN, c ? RT_SAMPLER_SOBOL : RT_SAMPLER_RANDOM,
                    c, 0, c ? 0.02 : 0, 0, RT_LIGHT_MIS};
        rt_renderer r;
        CHECK_EQ_INT(rt_render_init(&r, &s, a, &p), RT_OK);
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                uint64_t segs = 0;
                const uint32_t n = c ? rt_render_pilot(&r, x, y, &segs) : p.samples;
                double m[3] = {0}, m2[3] = {0};
                for (uint32_t k = 0; k < n; k++) {
                    rt_vec3 v = rt_render_sample(&r, x, y, k, &segs);
                    const double e[3] = {v.x, v.y, v.z};
                    for (int ch = 0; ch < 3; ch++)
                        m[ch] += e[ch] / n, m2[ch] += e[ch] * e[ch] / n;
                }
                for (int ch = 0; ch < 3; ch++) {
                    mean[c][ch] += m[ch] / (W * H);
                    var[c][ch] += (m2[ch] - m[ch] * m[ch]) / n / ((double)W * H * W * H);
                }
            }
    }
    printf("final scene, adaptive 0.02 (256 spp at most) against random at 1024 spp:");
    for (int ch = 0; ch < 3; ch++) {
        const double tol = 5 * sqrt(var[0][ch] + var[1][ch]);
        printf(" %.5f (off %+.5f, tolerance %.5f)", mean[1][ch], mean[1][ch] - mean[0][ch], tol);
        CHECK_NEAR(mean[1][ch], mean[0][ch], tol);
    }
    printf("\n");
    rt_accel_free(a);
    rt_scene_free(&s);
}

int main(void)
{
    check_rule();
    check_replay();
    check_furnace();
    check_bias_power();
    check_final_means();
    CHECK_DONE();
}
