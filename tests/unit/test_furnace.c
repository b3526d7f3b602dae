/* test_furnace.c - no bias, for every sampler and roulette setting:
 * - the furnace: a lambertian sphere of albedo a filling the view (through
 *   a lens: the lens pair is drawn too) under a uniform white sky. Every
 *   camera ray hits it, every scattered ray leaves it for the sky: each
 *   pixel is a in expectation, for each diffuse model. The roulette starts
 *   at the first bounce there, with a survival below 1, so a survivor's
 *   weight must be exactly 1/q;
 * - many bounces: the channel means of the final scene, and of a slab (the
 *   camera between two huge lambertian spheres of albedo 0.8 a unit apart,
 *   whose paths bounce a dozen times before they find the sky) against a
 *   reference from the random sampler without roulette at 4x the samples.
 *   In the slab a path that drew the same numbers at every bounce (say, a
 *   sampler that gave each bounce the same dimensions) drifts out in a
 *   straight line instead of a random walk, and comes out brighter.
 * Tolerances are 5 standard errors, measured from the samples' own spread
 * (which overstates the Sobol sampler's error: its strata make its mean
 * better than independent samples). Each configuration's fixed-point sums
 * from rt_render_rows (the packet path loop where the CPU has AVX) must
 * also equal the sums of its samples one by one (rt_render_sample). */
#include <stdlib.h>
#include <string.h>

#include "accel.h"
#include "check.h"
#include "core_internal.h"
#include "furnace.h"
#include "render.h"
#include "status.h"

typedef struct stats {
    double sum[3], sum2[3];
    long n;
} stats;

/* Every sample of the image, one by one; *same: their fixed-point sums
 * equal rt_render_rows' (with two threads). */
static void sample_stats(const rt_renderer *r, stats *st, int *same)
{
    const rt_job *p = &r->job;
    memset(st, 0, sizeof *st);
    size_t n = (size_t)p->width * p->height * 3;
    int64_t *acc = calloc(n, sizeof *acc), *one = calloc(n, sizeof *one);
    rt_render_rows(r, 0, p->height, 0, p->samples, acc, 2);
    for (uint32_t y = 0; y < p->height; y++)
        for (uint32_t x = 0; x < p->width; x++)
            for (uint32_t s = 0; s < p->samples; s++) {
                uint64_t segs = 0;
                rt_vec3 c = rt_render_sample(r, x, y, s, &segs);
                double v[3] = {c.x, c.y, c.z};
                int64_t *px = one + ((size_t)y * p->width + x) * 3;
                for (int k = 0; k < 3; k++) {
                    st->sum[k] += v[k];
                    st->sum2[k] += v[k] * v[k];
                    px[k] += rt_render_fix(v[k]);
                }
                st->n++;
            }
    *same = memcmp(acc, one, n * sizeof *acc) == 0;
    free(acc);
    free(one);
}

static double mean_of(const stats *st, int k) { return st->sum[k] / st->n; }

static double se_of(const stats *st, int k)
{
    double m = mean_of(st, k), var = st->sum2[k] / st->n - m * m;
    return sqrt((var > 0 ? var : 0) / st->n);
}

static const char *config_name(const rt_job *p)
{
    static char buf[64];
    snprintf(buf, sizeof buf, "%s%s", rt_sampler_name(p->sampler), p->roulette ? "+roulette" : "");
    return buf;
}

static void check_furnace(void)
{
    const rt_vec3 albedo = furnace_albedo();
    rt_scene s;
    rt_accel *a;
    furnace_scene(&s, &a);
    const double want[3] = {albedo.x, albedo.y, albedo.z};
    for (int model = 0; model < 3; model++)
        for (int kind = 0; kind < 2; kind++)
            for (int roulette = 0; roulette < 2; roulette++) {
                rt_job p = {24, 16, 128, 50, 3, (rt_diffuse)model, (rt_sampler_kind)kind, roulette, 1, 0, 0, RT_LIGHT_MIS};
                rt_renderer r;
                CHECK_EQ_INT(rt_render_init(&r, &s, a, &p), RT_OK);
                stats st;
                int same;
                sample_stats(&r, &st, &same);
                printf("furnace, %-10s %-15s:", rt_diffuse_name((rt_diffuse)model), config_name(&p));
                for (int k = 0; k < 3; k++) {
                    printf(" %.6f +- %.6f (want %.2f)", mean_of(&st, k), se_of(&st, k), want[k]);
                    /* 1e-12: rounding of the sum where every sample is a */
                    CHECK_NEAR(mean_of(&st, k), want[k], 5 * se_of(&st, k) + 1e-12);
                }
                printf("\n");
                CHECK(same);
                if (roulette) /* it played: some paths ended, the others weigh more */
                    CHECK(se_of(&st, 0) > 0);
            }
    rt_accel_free(a);
    rt_scene_free(&s);
}

static void check_many_bounces(const char *name, const rt_scene *sc)
{
    const rt_scene s = *sc;
    rt_accel *a;
    CHECK_EQ_INT(rt_accel_new(&a, &s, RT_ACCEL_BVH), RT_OK);
    rt_job ref_p = {24, 16, 1024, 50, 11, RT_DIFFUSE_LAMBERTIAN, RT_SAMPLER_RANDOM, 0, 0, 0, 0, RT_LIGHT_MIS};
    rt_renderer r;
    CHECK_EQ_INT(rt_render_init(&r, &s, a, &ref_p), RT_OK);
    stats ref;
    int same;
    sample_stats(&r, &ref, &same);
    printf("%s, reference (random, 1024 spp): %.5f %.5f %.5f\n", name, mean_of(&ref, 0), mean_of(&ref, 1),
           mean_of(&ref, 2));
    const struct {
        rt_sampler_kind kind;
        int roulette;
    } cfg[] = {{RT_SAMPLER_RANDOM, 1}, {RT_SAMPLER_SOBOL, 0}, {RT_SAMPLER_SOBOL, 1}};
    for (size_t c = 0; c < sizeof cfg / sizeof cfg[0]; c++) {
        rt_job p = {24, 16, 256, 50, 12, RT_DIFFUSE_LAMBERTIAN, cfg[c].kind, cfg[c].roulette, 0, 0, 0, RT_LIGHT_MIS};
        CHECK_EQ_INT(rt_render_init(&r, &s, a, &p), RT_OK);
        stats st;
        sample_stats(&r, &st, &same);
        printf("%s, %-15s (256 spp):", name, config_name(&p));
        for (int k = 0; k < 3; k++) {
            double tol = 5 * sqrt(se_of(&st, k) * se_of(&st, k) + se_of(&ref, k) * se_of(&ref, k));
            printf(" %.5f (off %+.5f, tolerance %.5f)", mean_of(&st, k), mean_of(&st, k) - mean_of(&ref, k), tol);
            CHECK_NEAR(mean_of(&st, k), mean_of(&ref, k), tol);
        }
        printf("\n");
        CHECK(same);
    }
    rt_accel_free(a);
}

int main(void)
{
    check_furnace();
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_final(&s, 5, 2), RT_OK);
    check_many_bounces("final scene", &s);
    rt_scene_free(&s);
    rt_scene_init(&s);
    CHECK_EQ_INT(rt_scene_add(&s, rt_v3(0, -1000, 0), 1000, rt_scene_lambertian(rt_v3(0.8, 0.8, 0.8))), RT_OK);
    CHECK_EQ_INT(rt_scene_add(&s, rt_v3(0, 1001, 0), 1000, rt_scene_lambertian(rt_v3(0.8, 0.8, 0.8))), RT_OK);
    s.sky_bottom = s.sky_top = rt_v3(1, 1, 1);
    s.camera = (rt_camera_desc){rt_v3(0, 0.5, 0), rt_v3(1, 0.5, 0), rt_v3(0, 1, 0), 60.0, 0.0, 1.0, 0};
    check_many_bounces("slab", &s);
    rt_scene_free(&s);
    CHECK_DONE();
}
