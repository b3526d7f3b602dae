/* test_adaptive.c - adaptive sampling (--noise-threshold):
 * - the stopping rule on samples of known spread;
 * - every pixel of a small final scene, replayed sample by sample
 *   (rt_render_sample): its sums are exactly those of its first n samples,
 *   no count before n met the threshold and n did (or n is -s), so the
 *   decision depends on that pixel's samples alone;
 * - bias: the furnace (a lambertian sphere of albedo a under a white sky,
 *   roulette from the first bounce) comes out a, within 5 standard errors,
 *   with the Sobol sampler. A stopping rule that looks at the samples is
 *   biased in principle: with independent random numbers, a pixel whose
 *   paths happened to survive the roulette more often looks brighter and
 *   less noisy, and stops sooner (here each sample is 0 or a / 0.8). This
 *   test bounds that at 2 % of a for --sampler random (measured: 1.3 % at
 *   threshold 0.05 in this worst case of a two-valued pixel); the Sobol
 *   points stratify the roulette's numbers, so the count of survivors
 *   hardly varies and the bias is below the noise. */
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
    /* 16 equal samples: no spread, which is taken as too few to tell (all
     * 16 paths survived a roulette, say), at any threshold */
    CHECK(!rt_render_converged(16 * 0.5, 16 * 0.25, 16, 0.5));
    CHECK(!rt_render_converged(0, 0, 16, 0.5));
    /* 8 zeros and 8 ones: mean 0.5, variance 16/15 x 0.25, standard error
     * 0.1291 of the mean, so a relative error of 0.2582 */
    CHECK(!rt_render_converged(8, 8, 16, 0.258));
    CHECK(rt_render_converged(8, 8, 16, 0.259));
    /* a dark pixel (mean 0.005) is held to RT_ADAPT_FLOOR instead: 0.01 and
     * 0 alternating, standard error 0.0012910 */
    CHECK(!rt_render_converged(0.08, 8 * 1e-4, 16, 0.0012910 / RT_ADAPT_FLOOR * 0.99));
    CHECK(rt_render_converged(0.08, 8 * 1e-4, 16, 0.0012910 / RT_ADAPT_FLOOR * 1.01));
}

/* The luminance of one sample as the renderer sums it. */
static double lum(rt_vec3 c)
{
    return (double)(rt_render_fix(c.x) + rt_render_fix(c.y) + rt_render_fix(c.z)) * (1.0 / (3.0 * RT_FIX_ONE));
}

static void check_replay(void)
{
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_final(&s, 5, 2), RT_OK);
    rt_accel *a;
    CHECK_EQ_INT(rt_accel_new(&a, &s, RT_ACCEL_BVH), RT_OK);
    for (int kind = 0; kind < 2; kind++) {
        rt_job p = {24, 16, 128, 50, 7, RT_DIFFUSE_LAMBERTIAN, (rt_sampler_kind)kind, 1, 0, 0.03, 0};
        rt_renderer r;
        CHECK_EQ_INT(rt_render_init(&r, &s, a, &p), RT_OK);
        CHECK_EQ_INT(r.lay.ch, 4);
        CHECK_EQ_INT(r.lay.count, 3);
        const size_t npix = (size_t)p.width * p.height;
        int64_t *acc = calloc(npix * r.lay.ch, sizeof *acc);
        rt_render_rows(&r, 0, p.height, 0, p.samples, acc, 2);
        unsigned early = 0, full = 0, bad_sums = 0, bad_stop = 0, bad_count = 0;
        for (uint32_t y = 0; y < p.height; y++)
            for (uint32_t x = 0; x < p.width; x++) {
                const int64_t *px = acc + ((size_t)y * p.width + x) * r.lay.ch;
                const uint32_t n = (uint32_t)px[3];
                int level = n == p.samples;
                for (uint32_t c = RT_ADAPT_FIRST; c < p.samples; c *= 2)
                    level |= n == c;
                bad_count += !level;
                early += n < p.samples;
                full += n == p.samples;
                int64_t sum[3] = {0, 0, 0};
                double l = 0, l2 = 0;
                for (uint32_t k = 0; k < n; k++) {
                    uint64_t segs = 0;
                    rt_vec3 c = rt_render_sample(&r, x, y, k, &segs);
                    sum[0] += rt_render_fix(c.x), sum[1] += rt_render_fix(c.y), sum[2] += rt_render_fix(c.z);
                    double v = lum(c);
                    l += v, l2 += v * v;
                    const uint32_t done = k + 1;
                    if (done % RT_ADAPT_FIRST == 0 && !((done / RT_ADAPT_FIRST) & (done / RT_ADAPT_FIRST - 1)) &&
                        done < p.samples)
                        bad_stop += rt_render_converged(l, l2, done, p.noise_threshold) != (done == n);
                }
                bad_sums += memcmp(sum, px, sizeof sum) != 0;
            }
        printf("%s: %u pixels stopped early, %u took all %u samples\n", rt_sampler_name(p.sampler), early, full,
               p.samples);
        CHECK_EQ_INT(bad_count, 0); /* every count is one of the fixed ones */
        CHECK_EQ_INT(bad_sums, 0);  /* the sums are the first n samples' */
        CHECK_EQ_INT(bad_stop, 0);  /* it stopped at the first count that met the threshold */
        CHECK(early > 0 && full > 0); /* both happen in this image: the checks above mean something */
        free(acc);
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
            rt_job p = {32, 24, 256, 50, 3, RT_DIFFUSE_LAMBERTIAN, (rt_sampler_kind)kind, roulette, 1, 0.05, 0};
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
                const double bound = p.sampler == RT_SAMPLER_SOBOL ? 0 : 0.02 * want[k];
                CHECK_NEAR(m[k], want[k], 5 * se + bound + 1e-9);
            }
            printf("\n");
            free(acc);
        }
    rt_accel_free(a);
    rt_scene_free(&s);
}

int main(void)
{
    check_rule();
    check_replay();
    check_furnace();
    CHECK_DONE();
}
