/* test_lanes.c - the book-2 path loop in AVX-512 lanes (path_lanes.c)
 * against the scalar loop (path2.c's trace2), pixel sums and ray segments
 * to the bit: book 2's Cornell box and quads, and the same with quads made
 * to be hard (a coplanar twin of a wall, so every hit on it ties; a quad
 * seen edge-on from the camera; a tiny one; one-sided and two-sided
 * lights facing both ways; a quad so far that its t overflows), with and
 * without the roulette, at depths from 1 to 40, on the scene's background
 * and under the sky, by brute force and with light sampling (MIS, and the
 * lights' estimate alone);
 * and which jobs and scenes run in the lanes at all. On a CPU without
 * AVX-512 the lanes never run: the test says so and checks that. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "accel.h"
#include "check.h"
#include "core_internal.h"
#include "path_lanes.h"
#include "render.h"
#include "scenes.h"
#include "rng.h"
#include "sample.h"
#include "status.h"
#include "world.h"

static int have_avx512(void)
{
#if defined(__x86_64__) && defined(__GNUC__)
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
#else
    return 0;
#endif
}

static uint32_t add_mat(rt_scene *s, uint32_t kind, rt_vec3 col, uint32_t flags)
{
    rt_material m = {.kind = kind, .albedo = col, .flags = flags, .emit = col};
    uint32_t k = 0;
    CHECK_EQ_INT(rt_scene_add_material(s, &m, &k), RT_OK);
    return k;
}

/* The quads that make the walls and lights hard for the lanes. */
static void add_hard_quads(rt_scene *s)
{
    const uint32_t red = add_mat(s, RT_MAT_LAMBERTIAN, rt_v3(0.9, 0.2, 0.1), 0);
    const uint32_t lit1 = add_mat(s, RT_MAT_EMITTER, rt_v3(4, 3, 2), 0);
    const uint32_t lit2 = add_mat(s, RT_MAT_EMITTER, rt_v3(1, 5, 9), RT_MAT_TWO_SIDED);
    const rt_vec3 from = s->camera.lookfrom, at = s->camera.lookat;
    const rt_vec3 mid = rt_v3_scale(rt_v3_add(from, at), 0.5), toward = rt_v3_sub(at, from);
    /* the floor's twin (cornell-box: the white floor y = 0; quads: none there) */
    CHECK_EQ_INT(rt_scene_add_quad(s, rt_v3(0, 0, 0), rt_v3(555, 0, 0), rt_v3(0, 0, 555), red, NULL), RT_OK);
    /* edge-on from the camera: its plane holds the camera's axis */
    CHECK_EQ_INT(rt_scene_add_quad(s, mid, rt_v3_scale(toward, 0.3), rt_v3(0, 80, 0), red, NULL), RT_OK);
    /* tiny, in the middle of the view */
    CHECK_EQ_INT(rt_scene_add_quad(s, at, rt_v3(0.5, 0, 0), rt_v3(0, 0.5, 0), lit2, NULL), RT_OK);
    /* lights facing the camera and away from it, one-sided and two-sided */
    CHECK_EQ_INT(rt_scene_add_quad(s, rt_v3(200, 100, 100), rt_v3(60, 0, 0), rt_v3(0, 60, 0), lit1, NULL), RT_OK);
    CHECK_EQ_INT(rt_scene_add_quad(s, rt_v3(300, 200, 150), rt_v3(0, 60, 0), rt_v3(60, 0, 0), lit1, NULL), RT_OK);
    CHECK_EQ_INT(rt_scene_add_quad(s, rt_v3(100, 300, 200), rt_v3(0, 50, 0), rt_v3(50, 0, 0), lit2, NULL), RT_OK);
    /* far off: a ray that meets its plane at a glancing angle has a t that
     * overflows, which no test may take for a hit */
    CHECK_EQ_INT(rt_scene_add_quad(s, rt_v3(-1e306, 1e306, 1e306), rt_v3(1e-8, 0, 0), rt_v3(0, 1e-8, 0), red, NULL),
                 RT_OK);
}

/* Nine more small lights, one-sided and two-sided: more than the lanes'
 * vector estimate takes (RT_LIGHTS_QUAD_ROWS), so each lane's goes to the
 * scalar rt_nee_direct. */
static void add_many_lights(rt_scene *s)
{
    const uint32_t lit1 = add_mat(s, RT_MAT_EMITTER, rt_v3(6, 2, 1), 0);
    const uint32_t lit2 = add_mat(s, RT_MAT_EMITTER, rt_v3(1, 2, 6), RT_MAT_TWO_SIDED);
    for (int i = 0; i < 9; i++)
        CHECK_EQ_INT(rt_scene_add_quad(s, rt_v3(60 + 50 * i, 500 - 20 * i, 100 + 30 * i), rt_v3(30, 0, 0),
                                       rt_v3(0, i % 2 ? 30 : -30, 30), i % 3 ? lit1 : lit2, NULL),
                     RT_OK);
}

/* The scene's render by the scalar loop and by the lanes, the same bits. */
static void check_same(const char *name, const rt_scene *s, const rt_job *job, int lanes)
{
    rt_accel *a;
    CHECK_EQ_INT(rt_accel_new(&a, s, RT_ACCEL_BVH), RT_OK);
    rt_renderer r;
    CHECK_EQ_INT(rt_render_init(&r, s, a, job), RT_OK);
    CHECK_EQ_INT(r.lanes, lanes);
    const size_t n = (size_t)job->width * job->height * 3;
    int64_t *ref = calloc(n, sizeof *ref), *alt = calloc(n, sizeof *alt);
    r.lanes = 0;
    const uint64_t segs_ref = rt_render_rows(&r, 0, job->height, 0, job->samples, ref, 1);
    uint64_t segs = 0;
    if (lanes) { /* the lanes over every pixel, in runs as team.c hands them, samples in two parts */
        r.lanes = 1;
        const long npix = (long)job->width * job->height;
        const uint32_t half = job->samples / 2;
        for (long i = 0; i < npix; i += 5) {
            const long e = i + 5 < npix ? i + 5 : npix;
            segs += rt_path_lanes_run(&r, 0, job->width, 0, 0, half, i, e, alt);
            segs += rt_path_lanes_run(&r, 0, job->width, 0, half, job->samples, i, e, alt);
        }
    }
    long same = 0, lit = 0;
    for (size_t i = 0; i < n; i++) {
        same += ref[i] == alt[i];
        lit += ref[i] != 0;
    }
    fprintf(stderr, "%s (%ux%u, %u spp, depth %u, roulette %d): %llu segments, %llu in the lanes, %ld of %zu sums "
            "the same, %ld not 0\n", name, job->width, job->height, job->samples, job->max_depth, job->roulette,
            (unsigned long long)segs_ref, (unsigned long long)segs, same, n, lit);
    if (lanes) {
        CHECK_EQ_INT(same, (long)n);
        CHECK_EQ_INT(segs, segs_ref);
        CHECK(lit >= 20); /* the light found, not only black on both sides */
    }
    free(ref);
    free(alt);
    rt_accel_free(a);
}

/* The lanes' quad test against brute force's (t and quad to the bit),
 * ray by ray: random rays in a crafted scene, and rays made for its edges:
 * a quad's corners and edges hit exactly, a coplanar twin (ties go to the
 * lower quad), denominators just below and above rt_quad_t's 1e-8, and a
 * far quad where t overflows. */
static void check_closest(void)
{
    rt_scene s;
    rt_scene_init(&s);
    const uint32_t w = add_mat(&s, RT_MAT_LAMBERTIAN, rt_v3(0.5, 0.5, 0.5), 0);
    rt_rng rq = rt_rng_for_stream(4, RT_STREAM_TEST);
    for (int i = 0; i < 6; i++) /* others about the square, any way round */
        CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(rt_rng_double(&rq) * 2 - 1, rt_rng_double(&rq) * 2 - 1, 1 + i),
                                       rt_sample_unit_vector(&rq), rt_sample_unit_vector(&rq), w, NULL),
                     RT_OK);
    CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(0, 0, 0), rt_v3(1, 0, 0), rt_v3(0, 1, 0), w, NULL), RT_OK);
    CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(0, 0, 0), rt_v3(1, 0, 0), rt_v3(0, 1, 0), w, NULL), RT_OK);
    CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(-1e306, 1e306, 1e306), rt_v3(1e-8, 0, 0), rt_v3(0, 1e-8, 0), w, NULL),
                 RT_OK);
    rt_world *wl, *wb;
    CHECK_EQ_INT(rt_world_build(&wl, &s, RT_WORLD_BVH, 0.0, 1.0), RT_OK);
    CHECK_EQ_INT(rt_world_build(&wb, &s, RT_WORLD_BRUTE, 0.0, 1.0), RT_OK);
    const uint32_t sq = s.shapes.quads.n - 3; /* the unit square; its twin next */
    rt_rng rng = rt_rng_for_stream(3, RT_STREAM_TEST);
    const int N = 8 * 4000;
    int same = 0, hits = 0, ties = 0, edges = 0;
    for (int g = 0; g < N / 8; g++) {
        rt_ray ray[8];
        for (int l = 0; l < 8; l++) {
            const int k = (8 * g + l) % 8;
            const double X = 0.3, dz = (k == 0 ? 0.99e-8 : 1.01e-8) * (rt_rng_double(&rng) < 0.5 ? 1 : -1);
            switch (k) {
            case 0: /* just below the 1e-8: no hit, though the point lies inside */
            case 1: /* just above it: a hit at t = X */
                ray[l] = (rt_ray){rt_v3(0.5 - X, 0.5, -dz * X), rt_v3(1, 0, dz)};
                break;
            case 2: /* a corner or an edge, exactly */
                ray[l] = (rt_ray){rt_v3((double)(g % 3) * 0.5, (double)(g / 3 % 3) * 0.5, -2), rt_v3(0, 0, 1)};
                break;
            case 3: /* glancing at the far quad's plane: t overflows */
                ray[l] = (rt_ray){rt_v3(1, 2, 3), rt_v3(1, 1, 1e-3 * rt_rng_double(&rng))};
                break;
            default: /* anywhere near the square, any direction */
                ray[l] = (rt_ray){rt_v3(rt_rng_double(&rng) * 3 - 1, rt_rng_double(&rng) * 3 - 1, rt_rng_double(&rng) * 4 - 2),
                                  rt_sample_unit_vector(&rng)};
            }
        }
        double t[8];
        int64_t id[8];
        CHECK_EQ_INT(rt_path_lanes_closest(wl, &s, ray, t, id), s.shapes.quads.n);
        for (int l = 0; l < 8; l++) {
            rt_whit h = {0, 0, 0, 0};
            const int hit = rt_world_closest(wb, &ray[l], 0.0, 0.001, INFINITY, &h);
            const int ok = hit ? id[l] == (int64_t)h.index && t[l] == h.t : id[l] == -1;
            same += ok;
            hits += hit;
            ties += hit && h.index == sq;
            edges += l % 8 == 2 && hit && h.index == sq;
            if (!ok && same + 5 > 8 * g + l)
                fprintf(stderr, "  ray %d: lanes quad %lld t %.17g, brute %d quad %u t %.17g\n", 8 * g + l,
                        (long long)id[l], t[l], hit, h.index, h.t);
        }
    }
    fprintf(stderr, "quad test: %d rays, %d hit (%d the twins' first, %d at corners and edges), %d the same as brute "
            "force\n", N, hits, ties, edges, same);
    CHECK_EQ_INT(same, N);
    CHECK(ties > N / 8 && edges > N / 16);
    rt_world_free(wl);
    rt_world_free(wb);
    rt_scene_free(&s);
}

int main(void)
{
    const int avx512 = have_avx512();
    if (!avx512)
        fprintf(stderr, "this CPU has no AVX-512 F and DQ: the lanes never run (checked below)\n");
    else
        check_closest();
    rt_job job = {.width = 24,
                  .height = 20,
                  .samples = 13,
                  .max_depth = 40,
                  .seed = 7,
                  .diffuse = RT_DIFFUSE_LAMBERTIAN,
                  .sampler = RT_SAMPLER_SOBOL,
                  .light = RT_LIGHT_BRUTE,
                  .roulette = 1};
    const char *names[2] = {"cornell-box", "quads"};
    for (int k = 0; k < 2; k++)
        for (int hard = 0; hard < 3; hard++) {
            rt_scene s;
            CHECK_EQ_INT(rt_scene_build_named(&s, names[k], 42, 11, NULL), RT_OK);
            if (hard == 1)
                add_hard_quads(&s);
            if (hard == 2)
                add_many_lights(&s);
            char name[64];
            snprintf(name, sizeof name, "%s%s", names[k],
                     hard == 1 ? " with hard quads" : hard == 2 ? " with nine more lights" : "");
            const uint32_t depths[3] = {40, 1, 3};
            const int modes[3] = {RT_LIGHT_BRUTE, RT_LIGHT_MIS, RT_LIGHT_NEE_ONLY};
            for (int m = 0; m < 3; m++)
                for (int d = 0; d < 3; d++) {
                    rt_job j = job;
                    j.light = modes[m];
                    j.max_depth = depths[d];
                    j.roulette = d != 1;
                    j.seed = 7 + (uint64_t)d;
                    char lname[96];
                    snprintf(lname, sizeof lname, "%s, %s", name,
                             m == 0 ? "brute force" : m == 1 ? "lights by MIS" : "lights' estimate alone");
                    check_same(lname, &s, &j, avx512);
                }
            /* under book 1's sky gradient instead of the scene's background */
            s.background_kind = RT_BACKGROUND_SKY;
            check_same(name, &s, &job, avx512);
            rt_scene_free(&s);
        }

    /* what runs in the lanes: with or without light sampling; not another
     * sampler or diffuse model, buffers, spheres, textures or media */
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_named(&s, "cornell-box", 42, 11, NULL), RT_OK);
    rt_accel *a, *brute;
    CHECK_EQ_INT(rt_accel_new(&a, &s, RT_ACCEL_BVH), RT_OK);
    CHECK_EQ_INT(rt_accel_new(&brute, &s, RT_ACCEL_BRUTE), RT_OK);
    rt_renderer r;
    CHECK_EQ_INT(rt_render_init(&r, &s, a, &job), RT_OK);
    CHECK_EQ_INT(r.lanes, avx512);
    rt_job lit = job;
    lit.light = RT_LIGHT_MIS;
    CHECK_EQ_INT(rt_render_init(&r, &s, a, &lit), RT_OK);
    CHECK_EQ_INT(r.lanes, avx512);
    rt_job rnd = job, hemi = job, aov = job, adapt = job;
    rnd.sampler = RT_SAMPLER_RANDOM;
    hemi.diffuse = RT_DIFFUSE_HEMISPHERE;
    aov.aov = RT_AOV_ALBEDO;
    adapt.noise_threshold = 0.05;
    const rt_job *no[4] = {&rnd, &hemi, &aov, &adapt};
    for (int i = 0; i < 4; i++) {
        CHECK_EQ_INT(rt_render_init(&r, &s, a, no[i]), RT_OK);
        CHECK_EQ_INT(r.lanes, 0);
    }
    CHECK_EQ_INT(rt_render_init(&r, &s, brute, &job), RT_OK); /* brute force stays the oracle */
    CHECK_EQ_INT(r.lanes, 0);
    rt_accel_free(a);
    /* a textured wall */
    rt_texture tex = {.kind = RT_TEX_SOLID, .color = {0.2, 0.4, 0.6}};
    uint32_t ti = 0;
    CHECK_EQ_INT(rt_scene_add_texture(&s, &tex, &ti), RT_OK);
    rt_material tm = {.kind = RT_MAT_LAMBERTIAN, .albedo = rt_v3(0.5, 0.5, 0.5), .texture = 1 + ti};
    uint32_t mi = 0;
    CHECK_EQ_INT(rt_scene_add_material(&s, &tm, &mi), RT_OK);
    CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(10, 10, 10), rt_v3(20, 0, 0), rt_v3(0, 20, 0), mi, NULL), RT_OK);
    CHECK_EQ_INT(rt_accel_new(&a, &s, RT_ACCEL_BVH), RT_OK);
    CHECK_EQ_INT(rt_render_init(&r, &s, a, &job), RT_OK);
    CHECK_EQ_INT(r.lanes, 0);
    rt_accel_free(a);
    rt_accel_free(brute);
    rt_scene_free(&s);
    const char *others[3] = {"simple-light", "cornell-smoke", "earth"};
    for (int i = 0; i < 3; i++) {
        CHECK_EQ_INT(rt_scene_build_named(&s, others[i], 42, 11, NULL), i < 2 ? RT_OK : RT_ENOFILE);
        if (i == 2)
            continue; /* no earth texture here: the scene is not built */
        CHECK_EQ_INT(rt_accel_new(&a, &s, RT_ACCEL_BVH), RT_OK);
        CHECK_EQ_INT(rt_render_init(&r, &s, a, &job), RT_OK);
        CHECK_EQ_INT(r.lanes, 0);
        rt_accel_free(a);
        rt_scene_free(&s);
    }
    CHECK_DONE();
}
