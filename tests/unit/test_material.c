/* test_material.c - metal reflection angle, dielectric total internal
 * reflection, attenuation never above 1, diffuse directions above the
 * surface, and each diffuse model's distribution of directions against its
 * law (chi-square), drawn by either sampler. */
#include "core_internal.h"
#include "check.h"
#include "material.h"
#include "rng.h"

/* Law of mu = cos(theta) between the scattered direction and the normal,
 * as a CDF on [0, 1]:
 * - lambertian (normal + random unit vector): pdf over solid angle
 *   cos(theta) / pi, so pdf(mu) = 2 mu and CDF mu^2;
 * - sphere (normal + random point in the unit ball, seed 002's first
 *   model): the point q is uniform in the unit ball centred on the normal's
 *   tip, which touches the surface at the origin. Along a direction at angle
 *   theta that ball spans r in [0, 2 cos(theta)], so the direction's pdf is
 *   (1 / (4 pi / 3)) * integral of r^2 dr = (2 cos(theta))^3 / 3 / (4 pi / 3)
 *   = 2 cos^3(theta) / pi - seed 002's cos^3 law, exactly. Hence
 *   pdf(mu) = 4 mu^3 and CDF mu^4;
 * - hemisphere (uniform): pdf 1 / (2 pi), so mu is uniform: CDF mu. */
static double cdf_lambertian(double mu) { return mu * mu; }
static double cdf_sphere(double mu) { return mu * mu * mu * mu; }
static double cdf_hemisphere(double mu) { return mu; }

#define BINS 20
/* Chi-square critical value at p = 0.001 with 19 degrees of freedom. */
#define CHI2_CRIT 43.82
#define PI 3.14159265358979323846

/* Chi-square of BINS equal-probability bins: under the right law, cdf(mu)
 * is uniform on [0, 1] (so every bin expects n / BINS samples, however
 * peaked the law). */
static double chi2_uniform(const double *u, long n, double (*cdf)(double))
{
    long obs[BINS] = {0};
    for (long i = 0; i < n; i++) {
        int b = (int)((cdf ? cdf(u[i]) : u[i]) * BINS);
        obs[b < 0 ? 0 : b >= BINS ? BINS - 1 : b]++;
    }
    double x = 0, e = (double)n / BINS;
    for (int b = 0; b < BINS; b++)
        x += (obs[b] - e) * (obs[b] - e) / e;
    return x;
}

/* Scatters n rays off a lambertian surface with normal nrm (tilted, so no
 * axis is favoured); stores mu = cos(theta) and the azimuth around the
 * normal as a fraction of a turn. With the Sobol sampler, blocks of 1024
 * samples of a pixel each, at bounces 0 to 4 (each its own pairs). */
static void diffuse_samples(rt_sampler_kind kind, rt_diffuse model, rt_vec3 nrm, long n, double *mu,
                            double *azimuth)
{
    rt_sampler smp = rt_sampler_from_rng(rt_rng_for_stream(1000 + model, RT_STREAM_TEST));
    rt_material m = {.kind = RT_MAT_LAMBERTIAN, .albedo = rt_v3(0.5, 0.5, 0.5), .fuzz = 0.0, .ior = 1.0};
    rt_surface s = {.p = rt_v3(0, 0, 0), .normal = nrm, .t = 1.0, .front_face = 1};
    rt_vec3 t1 = rt_v3_unit(rt_v3_cross(nrm, rt_v3(1, 0, 0))), t2 = rt_v3_cross(nrm, t1);
    rt_ray in = {rt_v3_add(nrm, rt_v3(0.3, 0, 0)), rt_v3_neg(nrm)};
    rt_sampler_pixel px;
    for (long i = 0; i < n; i++) {
        rt_vec3 att;
        rt_ray out;
        if (kind == RT_SAMPLER_SOBOL) {
            if ((i & 1023) == 0)
                rt_sampler_for_pixel(&px, kind, rt_rng_pixel_key(model, (uint64_t)(i >> 10)));
            smp = rt_sampler_start(&px, (uint32_t)(i & 1023));
            rt_sampler_bounce(&smp, (uint32_t)(i >> 10) % 5);
        }
        rt_material_scatter(&m, &in, &s, model, &smp, &att, &out);
        rt_vec3 d = rt_v3_unit(out.dir);
        mu[i] = rt_v3_dot(d, nrm);
        azimuth[i] = (atan2(rt_v3_dot(d, t2), rt_v3_dot(d, t1)) + PI) / (2 * PI);
    }
}

static void check_diffuse_laws(void)
{
    double (*law[3])(double) = {cdf_lambertian, cdf_sphere, cdf_hemisphere};
    static const char *names[3] = {"lambertian", "sphere", "hemisphere"};
    enum { N = 200000 };
    static double mu[N], azimuth[N];
    rt_vec3 nrm = rt_v3_unit(rt_v3(0.3, 0.8, -0.52));
    for (int kind = 0; kind < 2; kind++) {
        for (int model = 0; model < 3; model++) {
            diffuse_samples((rt_sampler_kind)kind, (rt_diffuse)model, nrm, N, mu, azimuth);
            double own = chi2_uniform(mu, N, law[model]);
            printf("%s diffuse %-10s: chi2 of cos(theta) against its law %.1f (critical %.2f)", rt_sampler_name(kind),
                   names[model], own, CHI2_CRIT);
            CHECK(own < CHI2_CRIT);
            /* The test tells the three laws apart: each sample set fails the
             * other two laws by a wide margin. */
            for (int other = 0; other < 3; other++) {
                if (other == model)
                    continue;
                double x = chi2_uniform(mu, N, law[other]);
                printf(", against %s %.0f", names[other], x);
                CHECK(x > 100 * CHI2_CRIT);
            }
            /* Every model is symmetric about the normal: uniform azimuth. */
            double xa = chi2_uniform(azimuth, N, NULL);
            printf("; azimuth %.1f\n", xa);
            CHECK(xa < CHI2_CRIT);
        }
    }
}

int main(void)
{
    rt_rng rng = rt_rng_for_stream(1, RT_STREAM_TEST);
    rt_sampler smp = rt_sampler_from_rng(rt_rng_for_stream(2, RT_STREAM_TEST));
    rt_surface s = {.p = rt_v3(0, 0, 0), .normal = rt_v3(0, 1, 0), .t = 1.0, .front_face = 1};
    rt_vec3 att;
    rt_ray out;

    /* Mirror metal: angle of reflection equals angle of incidence. */
    rt_material mirror = {.kind = RT_MAT_METAL, .albedo = rt_v3(0.7, 0.6, 0.5), .fuzz = 0.0, .ior = 1.0};
    rt_ray in = {rt_v3(-1, 1, 0), rt_v3(1, -1, 0)};
    CHECK(rt_material_scatter(&mirror, &in, &s, RT_DIFFUSE_LAMBERTIAN, &smp, &att, &out));
    rt_vec3 d = rt_v3_unit(out.dir);
    CHECK_NEAR(d.x, 1 / sqrt(2.0), 1e-12);
    CHECK_NEAR(d.y, 1 / sqrt(2.0), 1e-12);
    CHECK_NEAR(d.z, 0, 1e-12);
    CHECK_NEAR(att.x, 0.7, 0);

    /* Glass from inside at a grazing angle: total internal reflection,
     * always (no random choice involved). */
    rt_material glass = {.kind = RT_MAT_DIELECTRIC, .albedo = rt_v3(1, 1, 1), .fuzz = 0.0, .ior = 1.5};
    rt_surface inside = {.p = rt_v3(0, 0, 0), .normal = rt_v3(0, -1, 0), .t = 1.0};
    rt_ray graze = {rt_v3(-1, -0.2, 0), rt_v3(1, 0.2, 0)};
    int tir = 1;
    for (int i = 0; i < 1000; i++) {
        CHECK(rt_material_scatter(&glass, &graze, &inside, RT_DIFFUSE_LAMBERTIAN, &smp, &att, &out));
        tir &= out.dir.y < 0 && fabs(out.dir.x - rt_v3_unit(graze.dir).x) < 1e-12;
    }
    CHECK(tir);
    /* Head-on into glass: mostly refracts straight through (R0 = 4 %). */
    rt_ray head = {rt_v3(0, 1, 0), rt_v3(0, -1, 0)};
    int through = 0;
    for (int i = 0; i < 10000; i++) {
        rt_material_scatter(&glass, &head, &s, RT_DIFFUSE_LAMBERTIAN, &smp, &att, &out);
        through += out.dir.y < 0;
    }
    CHECK_NEAR(through / 10000.0, 0.96, 0.01);
    CHECK_NEAR(rt_material_reflectance(1.0, 1.0 / 1.5), 0.04, 1e-12);
    CHECK_NEAR(rt_material_reflectance(0.0, 1.5), 1.0, 1e-12);

    /* Attenuation never above 1 and diffuse directions stay above the
     * surface for every model and a random set of materials. */
    int ok_att = 1, ok_dir = 1;
    for (int i = 0; i < 20000; i++) {
        rt_material m;
        m.kind = (uint32_t)(i % 3);
        m.albedo = rt_v3(rt_rng_double(&rng), rt_rng_double(&rng), rt_rng_double(&rng));
        m.fuzz = 0.5 * rt_rng_double(&rng);
        m.ior = 1.0 + rt_rng_double(&rng);
        rt_ray r = {rt_v3(0, 1, 0), rt_v3(rt_rng_double(&rng) - 0.5, -1, rt_rng_double(&rng) - 0.5)};
        rt_diffuse model = (rt_diffuse)(i / 3 % 3);
        if (rt_material_scatter(&m, &r, &s, model, &smp, &att, &out)) {
            ok_att &= att.x <= 1 && att.y <= 1 && att.z <= 1 && att.x >= 0 && att.y >= 0 && att.z >= 0;
            if (m.kind == RT_MAT_LAMBERTIAN)
                ok_dir &= rt_v3_dot(out.dir, s.normal) >= 0;
            if (m.kind == RT_MAT_METAL)
                ok_dir &= rt_v3_dot(out.dir, s.normal) > 0;
        }
    }
    CHECK(ok_att);
    CHECK(ok_dir);
    check_diffuse_laws();
    CHECK_DONE();
}
