/* test_lights.c - light sampling (lights.h, nee.h) is unbiased: a point
 * on a diffuse plane under a rectangular or a spherical emitter against
 * the closed form of its irradiance, by light sampling alone, BSDF sampling alone and MIS
 * (also with a faint emitter and the shadow-ray roulette); which shadow
 * rays that roulette leaves to chance at a surface; a fuzzy metal
 * plane under that rectangle by the three;
 * a white furnace whose walls, a sphere and a moving sphere emit, with a
 * white medium inside (every pixel's radiance is the walls'), also with
 * a glass sphere that the diffuse vertices aim at (nee.h), and without
 * the medium, where they estimate the light through it (caustic.h); the
 * light book3-final's glass sphere focuses on its floor, through the
 * sphere and by the scattered paths alone; the
 * cornell-box's and cornell-smoke's channel means with and without light
 * sampling. Each
 * within four standard errors, from the random sampler's independent
 * samples. And the emission a shadow ray finds (rt_nee_emitted) on each
 * face of a two-sided, a one-sided and a textured emitter. */
#include <math.h>
#include <stdlib.h>

#include "check.h"
#include "core_internal.h"
#include "lights.h"
#include "nee.h"
#include "scenes.h"
#include "status.h"
#include "world.h"

static const char *const MODE[] = {"MIS", "BSDF sampling", "light sampling"};

/* Mean and standard error of n samples of pixel (x, y), channel 0..2. */
typedef struct stat {
    double sum[3], sum2[3];
    uint64_t n;
} stat;

static void add_pixel(stat *st, const rt_renderer *r, uint32_t x, uint32_t y, uint32_t n)
{
    uint64_t segs = 0;
    double s[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
    for (uint32_t k = 0; k < n; k++) {
        const rt_vec3 c = rt_render_sample(r, x, y, k, &segs);
        const double v[3] = {c.x, c.y, c.z};
        for (int i = 0; i < 3; i++)
            s[i] += v[i], s2[i] += v[i] * v[i];
    }
    /* the pixel's mean, and its variance over n, for the image's mean */
    for (int i = 0; i < 3; i++) {
        st->sum[i] += s[i] / n;
        st->sum2[i] += (s2[i] / n - (s[i] / n) * (s[i] / n)) / (n - 1);
    }
    st->n++;
}
static double mean(const stat *st, int i) { return st->sum[i] / (double)st->n; }
static double se(const stat *st, int i) { return sqrt(st->sum2[i]) / (double)st->n; }

/* roulette: Russian roulette on (paths past its depth, faint shadow rays). */
static rt_renderer renderer(const rt_scene *s, rt_accel **a, uint32_t w, uint32_t h, uint32_t depth, uint32_t light,
                            int roulette)
{
    rt_renderer r;
    CHECK_EQ_INT(rt_accel_new(a, s, RT_ACCEL_BVH), RT_OK);
    const rt_job job = {w, h, 1, depth, 5, RT_DIFFUSE_LAMBERTIAN, RT_SAMPLER_RANDOM, roulette, 0, 0, 0, light};
    CHECK_EQ_INT(rt_render_init(&r, s, *a, &job), RT_OK);
    return r;
}

/* The form factor from a point to the rectangle [0, a] x [0, b] parallel
 * to its plane at height 1, one corner straight above it (odd in a and
 * in b, so rectangles anywhere follow by adding and subtracting). */
static double corner(double a, double b)
{
    const double ra = sqrt(1 + a * a), rb = sqrt(1 + b * b);
    return (a / ra * atan(b / ra) + b / rb * atan(a / rb)) / (2 * 3.14159265358979323846);
}

/* Plane y = 0 (albedo 0.5) seen at the origin under an emitter of
 * radiance 4: the rectangle x in [0.5, 1.5], z in [-0.5, 0.25] at height
 * 1, facing down (radiance off the plane: albedo / pi x irradiance =
 * albedo x L x form factor), or the sphere of radius 0.5 at height 2
 * (albedo x L x sin^2 of its half-angle). faint: radiance 0.04 with the
 * roulette on, so that nee.c's shadow-ray roulette keeps few shadow rays
 * (their light divided by the chance). */
static void check_analytic(int sphere, int faint)
{
    const double x0 = 0.5, x1 = 1.5, z0 = -0.5, z1 = 0.25, L = faint ? 0.04 : 4, rho = 0.5, rs = 0.5, hs = 2;
    const double want = sphere ? rho * L * rs * rs / (hs * hs)
                               : rho * L * (corner(x1, z1) - corner(x0, z1) - corner(x1, z0) + corner(x0, z0));
    rt_scene s;
    rt_scene_init(&s);
    uint32_t white, light;
    rt_material m = rt_scene_lambertian(rt_v3(rho, rho, rho)), e = rt_scene_emitter(rt_v3(L, L, L), 0);
    CHECK_EQ_INT(rt_scene_add_material(&s, &m, &white), RT_OK);
    CHECK_EQ_INT(rt_scene_add_material(&s, &e, &light), RT_OK);
    CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(-10, 0, -10), rt_v3(0, 0, 20), rt_v3(20, 0, 0), white, NULL), RT_OK);
    if (sphere)
        CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(0, hs, 0), rs, light), RT_OK);
    else
        CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(x0, 1, z0), rt_v3(x1 - x0, 0, 0), rt_v3(0, 0, z1 - z0), light, NULL),
                     RT_OK);
    s.background_kind = RT_BACKGROUND_COLOR;
    s.background = rt_v3(0, 0, 0);
    s.camera = (rt_camera_desc){rt_v3(-1, 1, 0), rt_v3(0, 0, 0), rt_v3(0, 1, 0), 1e-4, 0.0, 1.0, RT_PIXELS_BOOK2};
    for (uint32_t mode = RT_LIGHT_MIS; mode <= RT_LIGHT_NEE_ONLY; mode++) {
        rt_accel *a;
        const rt_renderer r = renderer(&s, &a, 1, 1, 2, mode, faint);
        CHECK(mode == RT_LIGHT_BRUTE ? r.lights == NULL : r.lights != NULL && rt_lights_count(r.lights) == 1);
        stat st = {{0}, {0}, 0};
        add_pixel(&st, &r, 0, 0, 200000);
        fprintf(stderr, "analytic %s%s, %s: %.5f, the closed form %.5f (se %.5f)\n", faint ? "faint " : "",
                sphere ? "sphere" : "rectangle", MODE[mode], mean(&st, 0), want, se(&st, 0));
        CHECK_NEAR(mean(&st, 0), want, 4 * se(&st, 0));
        rt_accel_free(a);
    }
    rt_scene_free(&s);
}

/* check_analytic's rectangle, facing down at radiance L (one-sided), over
 * a plane of material `plane`, seen at the origin in a 1 x 1 image. */
static void under_rectangle(rt_scene *s, rt_material plane, double L)
{
    rt_scene_init(s);
    uint32_t floor, light;
    rt_material e = rt_scene_emitter(rt_v3(L, L, L), 0);
    CHECK_EQ_INT(rt_scene_add_material(s, &plane, &floor), RT_OK);
    CHECK_EQ_INT(rt_scene_add_material(s, &e, &light), RT_OK);
    CHECK_EQ_INT(rt_scene_add_quad(s, rt_v3(-10, 0, -10), rt_v3(0, 0, 20), rt_v3(20, 0, 0), floor, NULL), RT_OK);
    CHECK_EQ_INT(rt_scene_add_quad(s, rt_v3(0.5, 1, -0.5), rt_v3(1, 0, 0), rt_v3(0, 0, 0.75), light, NULL), RT_OK);
    s->background_kind = RT_BACKGROUND_COLOR;
    s->background = rt_v3(0, 0, 0);
    s->camera = (rt_camera_desc){rt_v3(-1, 1, 0), rt_v3(0, 0, 0), rt_v3(0, 1, 0), 1e-4, 0.0, 1.0, RT_PIXELS_BOOK2};
}

/* A fuzzy metal plane (albedo 0.8) under check_analytic's rectangle, seen
 * where it mirrors the rectangle: its metal vertex samples the light
 * (rt_warp_fuzz_pdf's density of its scattered directions), so MIS and
 * light sampling alone must give the mean of BSDF sampling alone; fuzz
 * 0.3, and 1 (the largest a material has: the ball of offsets reaches the
 * origin). */
static void check_metal(double fuzz)
{
    rt_scene s;
    under_rectangle(&s, rt_scene_metal(rt_v3(0.8, 0.8, 0.8), fuzz), 4);
    stat st[3];
    for (uint32_t mode = RT_LIGHT_MIS; mode <= RT_LIGHT_NEE_ONLY; mode++) {
        rt_accel *a;
        const rt_renderer r = renderer(&s, &a, 1, 1, 2, mode, 0);
        st[mode] = (stat){{0}, {0}, 0};
        add_pixel(&st[mode], &r, 0, 0, 200000);
        fprintf(stderr, "fuzzy metal %.1f, %s: %.5f (se %.5f)\n", fuzz, MODE[mode], mean(&st[mode], 0),
                se(&st[mode], 0));
        rt_accel_free(a);
    }
    CHECK(mean(&st[RT_LIGHT_BRUTE], 0) > 0.1); /* the light is in view */
    for (uint32_t mode = RT_LIGHT_MIS; mode <= RT_LIGHT_NEE_ONLY; mode += 2) {
        const double e0 = se(&st[mode], 0), e1 = se(&st[RT_LIGHT_BRUTE], 0);
        CHECK_NEAR(mean(&st[mode], 0), mean(&st[RT_LIGHT_BRUTE], 0), 4 * sqrt(e0 * e0 + e1 * e1));
    }
    rt_scene_free(&s);
}

/* A box whose six walls emit 1 from both faces, around a white sphere, a
 * white floor, a sphere and a moving sphere that emit 1, all in white fog:
 * radiance 1 everywhere (up to paths longer than the depth limit). glass:
 * and a glass sphere (lossless), a sampling target of the white surfaces'
 * scattering (their mixture's density must be right for the mean to be 1). */
static void check_furnace(int glass, int fog)
{
    rt_scene s;
    rt_scene_init(&s);
    uint32_t white, wall, glow, fogm;
    rt_material m = rt_scene_lambertian(rt_v3(1, 1, 1)), e = rt_scene_emitter(rt_v3(1, 1, 1), 1),
                g = rt_scene_emitter(rt_v3(1, 1, 1), 0), f = rt_scene_isotropic(rt_v3(1, 1, 1));
    CHECK_EQ_INT(rt_scene_add_material(&s, &m, &white), RT_OK);
    CHECK_EQ_INT(rt_scene_add_material(&s, &e, &wall), RT_OK);
    CHECK_EQ_INT(rt_scene_add_material(&s, &g, &glow), RT_OK);
    CHECK_EQ_INT(rt_scene_add_material(&s, &f, &fogm), RT_OK);
    CHECK_EQ_INT(rt_scene_add_box(&s, rt_v3(-5, -5, -5), rt_v3(5, 5, 5), wall, NULL), RT_OK);
    CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(0, 0, 0), 1, white), RT_OK);
    CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(2, 0.5, 0), 0.5, glow), RT_OK);
    CHECK_EQ_INT(rt_scene_add_mover(&s, rt_v3(-2, 0, 0), rt_v3(-2, 1, 0), 0.5, glow, NULL), RT_OK);
    CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(-4, -2, -4), rt_v3(8, 0, 0), rt_v3(0, 0, 8), white, NULL), RT_OK);
    if (fog)
        CHECK_EQ_INT(rt_scene_add_medium_sphere(&s, rt_v3(0, 0, 0), 3, 0.3, fogm), RT_OK);
    if (glass) {
        uint32_t clear;
        rt_material d = rt_scene_dielectric(1.5);
        CHECK_EQ_INT(rt_scene_add_material(&s, &d, &clear), RT_OK);
        CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(0, -1.2, 2), 0.7, clear), RT_OK);
    }
    s.background_kind = RT_BACKGROUND_COLOR;
    s.background = rt_v3(0, 0, 0);
    s.camera = (rt_camera_desc){rt_v3(0, 0, 4.5), rt_v3(0, 0, 0), rt_v3(0, 1, 0), 70, 0.0, 1.0, RT_PIXELS_BOOK2};
    rt_accel *a;
    const rt_renderer r = renderer(&s, &a, 8, 8, 50, RT_LIGHT_MIS, 0);
    CHECK(r.lights != NULL && rt_lights_count(r.lights) == 8);
    CHECK_EQ_INT(rt_lights_target_count(r.lights), glass ? 1 : 0);
    CHECK_EQ_INT(r.light_targets, glass ? 1 : 0);
    /* a sampled light's material and place in the list are its shape's */
    rt_rng rng = rt_rng_for_stream(7, 1);
    int same = 0;
    for (int k = 0; k < 64; k++) {
        const rt_vec3 p = rt_v3(rt_rng_double(&rng) * 4 - 2, rt_rng_double(&rng) * 4 - 2, rt_rng_double(&rng) * 4 - 2);
        rt_light_dir ld;
        if (!rt_lights_sample(r.lights, p, 0.5, rt_rng_double(&rng), rt_rng_next(&rng), &ld)) {
            same++;
            continue;
        }
        const rt_whit h = {1.0, ld.kind, ld.index, 0};
        same += ld.material == rt_world_material(r.world, &h) &&
                rt_lights_pdf_of(r.lights, ld.light, p, 0.5, ld.dir, 1.5) ==
                    rt_lights_pdf(r.lights, p, 0.5, ld.dir, ld.kind, ld.index, 1.5);
    }
    CHECK_EQ_INT(same, 64);
    stat st = {{0}, {0}, 0};
    for (uint32_t y = 0; y < 8; y++)
        for (uint32_t x = 0; x < 8; x++)
            add_pixel(&st, &r, x, y, 4000);
    fprintf(stderr, "furnace with emitters%s%s: %.5f, want 1 (se %.5f)\n", fog ? " and fog" : "",
            glass ? (fog ? " and glass" : " and glass, light through it estimated (caustic.h)") : "", mean(&st, 1),
            se(&st, 1));
    CHECK_NEAR(mean(&st, 1), 1.0, 4 * se(&st, 1));
    rt_accel_free(a);
    rt_scene_free(&s);
}

/* A named scene's mean colour, with and without light sampling: the
 * cornell-box, and cornell-smoke, whose camera rays cross its smoke (the
 * in-scattering along them, path2.c). */
static void check_cornell(const char *name)
{
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_named(&s, name, 42, 0, NULL), RT_OK);
    stat st[2] = {{{0}, {0}, 0}, {{0}, {0}, 0}};
    for (uint32_t mode = RT_LIGHT_MIS; mode <= RT_LIGHT_BRUTE; mode++) {
        rt_accel *a;
        const rt_renderer r = renderer(&s, &a, 12, 12, 6, mode, 0);
        for (uint32_t y = 0; y < 12; y++)
            for (uint32_t x = 0; x < 12; x++)
                add_pixel(&st[mode], &r, x, y, mode == RT_LIGHT_MIS ? 512 : 8192);
        rt_accel_free(a);
    }
    for (int i = 0; i < 3; i++) {
        const double err = sqrt(se(&st[0], i) * se(&st[0], i) + se(&st[1], i) * se(&st[1], i));
        fprintf(stderr, "%s channel %d: %.5f with light sampling, %.5f without (se %.5f)\n", name, i,
                mean(&st[0], i), mean(&st[1], i), err);
        CHECK_NEAR(mean(&st[0], i), mean(&st[1], i), 4 * err);
    }
    rt_scene_free(&s);
}

/* book3-final's caustic, the light its glass sphere focuses onto the
 * floor in its own shadow: pixels of the spot (128 x 128: x 72 to 93, y
 * 110 to 118) at depth 4 (the camera's ray, the floor, the two
 * refractions and the light), with the light through the sphere estimated
 * at the floor (caustic.h) and found by the scattered paths alone
 * (no_caustic): the same means within four standard errors. */
static void check_caustic(void)
{
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_named(&s, "book3-final", 42, 0, NULL), RT_OK);
    stat st[2] = {{{0}, {0}, 0}, {{0}, {0}, 0}};
    for (int off = 0; off <= 1; off++) {
        rt_accel *a;
        rt_renderer r = renderer(&s, &a, 128, 128, 4, RT_LIGHT_MIS, 0);
        r.no_caustic = off;
        for (uint32_t y = 110; y <= 118; y += 4)
            for (uint32_t x = 72; x <= 93; x += 3)
                add_pixel(&st[off], &r, x, y, off ? 65536 : 8192);
        rt_accel_free(a);
    }
    for (int i = 0; i < 3; i++) {
        const double err = sqrt(se(&st[0], i) * se(&st[0], i) + se(&st[1], i) * se(&st[1], i));
        fprintf(stderr, "book3-final's caustic, channel %d: %.5f through the sphere (se %.5f), %.5f by the scattered "
                        "paths (se %.5f)\n", i, mean(&st[0], i), se(&st[0], i), mean(&st[1], i), se(&st[1], i));
        CHECK_NEAR(mean(&st[0], i), mean(&st[1], i), 4 * err);
    }
    rt_scene_free(&s);
}

/* The book-2 loop's numbers drawn ahead of the walk (path2.c's
 * look_ahead) against drawn after it: scene `name` at 8 x 8, 8 spp, Sobol,
 * with and without light sampling, the same sums to the bit. */
static void check_look_ahead(const char *name)
{
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_named(&s, name, 42, 0, NULL), RT_OK);
    for (uint32_t mode = RT_LIGHT_MIS; mode <= RT_LIGHT_BRUTE; mode++) {
        rt_accel *a;
        CHECK_EQ_INT(rt_accel_new(&a, &s, RT_ACCEL_BVH), RT_OK);
        const rt_job job = {8, 8, 8, 40, 5, RT_DIFFUSE_LAMBERTIAN, RT_SAMPLER_SOBOL, 1, 0, 0, 0, mode};
        rt_renderer r;
        CHECK_EQ_INT(rt_render_init(&r, &s, a, &job), RT_OK);
        const size_t n = (size_t)8 * 8 * r.lay.ch;
        int64_t *ahead = calloc(n, sizeof *ahead), *after = calloc(n, sizeof *after);
        CHECK(ahead && after);
        rt_render_rows(&r, 0, 8, 0, 8, ahead, 1);
        r.no_look_ahead = 1;
        rt_render_rows(&r, 0, 8, 0, 8, after, 1);
        size_t differ = 0, lit = 0;
        for (size_t i = 0; i < n; i++)
            differ += ahead[i] != after[i], lit += ahead[i] != 0;
        fprintf(stderr, "%s (%s): %zu of %zu sums differ with the numbers drawn after the walk (%zu not 0)\n",
                name, MODE[mode], differ, n, lit);
        CHECK_EQ_INT(differ, 0);
        CHECK(lit > n / 8);
        free(ahead);
        free(after);
        rt_accel_free(a);
    }
    rt_scene_free(&s);
}

/* rt_nee_emitted from below (the front) and above (the back) of three
 * quads facing -y: two-sided (4), one-sided (2: nothing from the back),
 * two-sided with a solid texture (1, 2, 3) over an emission of 9 (the
 * texture's value counts). */
static void check_emitted(void)
{
    rt_scene s;
    rt_scene_init(&s);
    uint32_t two, one, tex, textured;
    const rt_texture solid = {.kind = RT_TEX_SOLID, .color = {1, 2, 3}};
    rt_material e2 = rt_scene_emitter(rt_v3(4, 4, 4), 1), e1 = rt_scene_emitter(rt_v3(2, 2, 2), 0);
    CHECK_EQ_INT(rt_scene_add_material(&s, &e2, &two), RT_OK);
    CHECK_EQ_INT(rt_scene_add_material(&s, &e1, &one), RT_OK);
    CHECK_EQ_INT(rt_scene_add_texture(&s, &solid, &tex), RT_OK);
    rt_material et = rt_scene_textured(rt_scene_emitter(rt_v3(9, 9, 9), 1), tex);
    CHECK_EQ_INT(rt_scene_add_material(&s, &et, &textured), RT_OK);
    const uint32_t mats[3] = {two, one, textured};
    for (int i = 0; i < 3; i++)
        CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(2 * i, 1, 0), rt_v3(1, 0, 0), rt_v3(0, 0, 1), mats[i], NULL), RT_OK);
    s.background_kind = RT_BACKGROUND_COLOR;
    s.background = rt_v3(0, 0, 0);
    s.camera = (rt_camera_desc){rt_v3(0, 0, -5), rt_v3(0, 0, 0), rt_v3(0, 1, 0), 40, 0.0, 1.0, RT_PIXELS_BOOK2};
    rt_accel *a;
    const rt_renderer r = renderer(&s, &a, 1, 1, 2, RT_LIGHT_MIS, 0);
    /* channels 0 and 1, from below and from above */
    const double want[3][2][2] = {{{4, 4}, {4, 4}}, {{2, 2}, {0, 0}}, {{1, 2}, {1, 2}}};
    for (int i = 0; i < 3; i++)
        for (int side = 0; side < 2; side++) {
            const rt_ray ray = {rt_v3(2 * i + 0.5, side ? 2 : 0, 0.5), rt_v3(0, side ? -1 : 1, 0)};
            rt_whit h;
            CHECK(rt_nee_closest(&r, &ray, 0.0, NULL, &h));
            const rt_vec3 le = rt_nee_emitted(&r, &h, &ray, 0.0);
            CHECK_NEAR(le.x, want[i][side][0], 0.0);
            CHECK_NEAR(le.y, want[i][side][1], 0.0);
        }
    rt_accel_free(a);
    rt_scene_free(&s);
}

/* Which shadow rays the shadow-ray roulette (nee.c) leaves to chance:
 * check_analytic's rectangle at radiance L over the plane (albedo 0.5),
 * whose shadow rays' unoccluded light is 0.5 L times the BSDF over the
 * light's density d^3 / 0.75, for a point at distance d in [1.118, 1.871]
 * of the origin. A lambertian plane (cos / pi = 1 / (pi d)): 0.119 L / d^4,
 * at L = 0.6 from 0.0058 to 0.046, above the surfaces' threshold (0.005),
 * so the roulette traces every one (the same ray segments with it as
 * without: the paths end at depth 2, before their own roulette); at L =
 * 0.04 all below it, so it traces fewer. An isotropic one (1 / 4 pi, the
 * media's threshold, 0.05): 0.0298 L / d^3, at L = 2 from 0.0089 to 0.043,
 * so fewer. */
static void check_shadow_roulette(void)
{
    const struct {
        int iso;
        double L;
        int all;
    } cases[] = {{0, 0.6, 1}, {0, 0.04, 0}, {1, 2.0, 0}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const double L = cases[i].L;
        const rt_vec3 half = rt_v3(0.5, 0.5, 0.5);
        rt_scene s;
        under_rectangle(&s, cases[i].iso ? rt_scene_isotropic(half) : rt_scene_lambertian(half), L);
        uint64_t segs[2] = {0, 0};
        for (int roulette = 0; roulette <= 1; roulette++) {
            rt_accel *a;
            const rt_renderer r = renderer(&s, &a, 1, 1, 2, RT_LIGHT_MIS, roulette);
            for (uint32_t k = 0; k < 20000; k++)
                (void)rt_render_sample(&r, 0, 0, k, &segs[roulette]);
            rt_accel_free(a);
        }
        fprintf(stderr, "shadow-ray roulette, %s plane, radiance %g: %llu ray segments without, %llu with\n",
                cases[i].iso ? "isotropic" : "lambertian", L, (unsigned long long)segs[0],
                (unsigned long long)segs[1]);
        if (cases[i].all)
            CHECK_EQ_INT(segs[1], segs[0]);
        else
            CHECK(segs[1] < segs[0] - 1000);
        rt_scene_free(&s);
    }
}

int main(void)
{
    check_emitted();
    for (int faint = 0; faint <= 1; faint++) {
        check_analytic(0, faint);
        check_analytic(1, faint);
    }
    check_shadow_roulette();
    check_metal(0.3);
    check_metal(1.0);
    check_furnace(0, 1);
    check_furnace(1, 1);
    check_furnace(1, 0);
    check_caustic();
    check_cornell("cornell-box");
    check_cornell("cornell-smoke");
    check_look_ahead("cornell-box");
    check_look_ahead("cornell-smoke");
    check_look_ahead("book3-final");
    CHECK_DONE();
}
