/* test_accel.c - the BVH, with each of its box tests (the CPU's best, AVX
 * where present; SSE2, what x86-64 CPUs without AVX run; the portable scalar
 * one, what non-x86 builds run), must return the same closest hit as brute
 * force (the correctness oracle) for many random rays in random
 * scenes: rays from outside, from inside spheres, from surface points (as
 * bounces start), and grazing rays tangent to a sphere. Scenes with very
 * large spheres also check the spheres the tree leaves out (rt_bvh_outside). */
#include <stdlib.h>

#include "core_internal.h"
#include "accel.h"
#include "bvh.h"
#include "check.h"
#include "rng.h"
#include "status.h"

static rt_vec3 rnd_dir(rt_rng *r)
{
    for (;;) {
        rt_vec3 v = rt_v3(2 * rt_rng_double(r) - 1, 2 * rt_rng_double(r) - 1, 2 * rt_rng_double(r) - 1);
        double l = rt_v3_len2(v);
        if (l > 1e-6 && l <= 1)
            return rt_v3_scale(v, (0.1 + 3 * rt_rng_double(r)) / sqrt(l)); /* unnormalised */
    }
}

/* The core's leaf size: 1 unless it was built with another LEAF_MAX (the
 * test_accel_leaf4 build), which makes the traversals' leaves of several
 * spheres run here too. */
#ifdef LEAF_MAX
#define LEAF_MAX_TEST LEAF_MAX
#else
#define LEAF_MAX_TEST 1
#endif

static long mismatches, rays, hits;
static int scenes_outside;      /* random scenes in which the tree leaves spheres out */
#if LEAF_MAX_TEST > 1
static int scenes_multi_leaves; /* scenes with leaves of several spheres */
#endif

/* One intersector's answer against brute force's: the same sphere and the
 * same t to the bit, even in an exact tie (the lower index wins it,
 * rt_sphere_closer). */
static void check_same(const char *name, int ha, rt_hit a, int hb, rt_hit b, const rt_ray *ray)
{
    if (ha == hb && (!ha || (a.t == b.t && a.prim == b.prim)))
        return;
    if (mismatches < 5)
        fprintf(stderr, "mismatch: %s %d prim %u t %.17g / brute %d prim %u t %.17g; ray o=(%g %g %g) d=(%g %g %g)\n",
                name, ha, a.prim, a.t, hb, b.prim, b.t, ray->orig.x, ray->orig.y, ray->orig.z, ray->dir.x, ray->dir.y,
                ray->dir.z);
    mismatches++;
}

/* Totals of rt_bvh_closest_counted over the random rays. */
static rt_bvh_counts counted;

/* The box tests: rt_accel_closest with these kinds. Each must match brute
 * force, sphere and t, so they match each other. */
#define N_BOX_TESTS 3
static const rt_accel_kind box_tests[N_BOX_TESTS] = {RT_ACCEL_BVH, RT_ACCEL_BVH_SSE, RT_ACCEL_BVH_SCALAR};

static void compare(const rt_accel *const bvh[N_BOX_TESTS], const rt_accel *brute, const rt_ray *ray, double tmin)
{
    rt_hit b = {0, 0};
    int hb = rt_accel_closest(brute, ray, tmin, INFINITY, &b);
    rays++;
    hits += hb;
    for (int k = 0; k < N_BOX_TESTS; k++) {
        rt_hit a = {0, 0};
        int ha = rt_accel_closest(bvh[k], ray, tmin, INFINITY, &a);
        check_same(rt_accel_name(box_tests[k]), ha, a, hb, b, ray);
    }
    rt_hit c = {0, 0};
    int hc = rt_bvh_closest_counted(rt_accel_bvh(bvh[0]), ray, tmin, INFINITY, &c, &counted);
    check_same("bvh-counted", hc, c, hb, b, ray);
}

/* Packets of rays through rt_bvh_closest_packet (the AVX packet traversal
 * where the CPU has it), each ray's answer against brute force's. */
static long packet_rays;

static void compare_packet(const rt_bvh *b, const rt_accel *brute, const rt_ray *rays, int n, double tmin)
{
    rt_hit h[8] = {{0, 0}};
    int found = rt_bvh_closest_packet(b, rays, n, tmin, INFINITY, h);
    CHECK_EQ_INT(found >> n, 0);
    for (int k = 0; k < n; k++) {
        rt_hit bh = {0, 0};
        int hb = rt_accel_closest(brute, &rays[k], tmin, INFINITY, &bh);
        check_same("packet", (found >> k) & 1, h[k], hb, bh, &rays[k]);
        packet_rays++;
    }
}

/* An empty scene with one grey lambertian material (index 0). */
static void grey_scene(rt_scene *s)
{
    rt_scene_init(s);
    rt_material m = {.kind = RT_MAT_LAMBERTIAN, .albedo = rt_v3(0.5, 0.5, 0.5), .fuzz = 0, .ior = 1};
    CHECK_EQ_INT(rt_scene_add_material(s, &m, NULL), RT_OK);
}

/* The counts on a scene whose tree is known: spheres at x = 0, 100 and 200
 * (radius 1) give a root with three leaves of one sphere each. */
static void check_counts(void)
{
    rt_scene s;
    grey_scene(&s);
    for (int i = 0; i < 3; i++)
        CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(100.0 * i, 0, 0), 1.0, 0), RT_OK);
    rt_bvh *b;
    CHECK_EQ_INT(rt_bvh_build(&b, &s), RT_OK);
    int nodes, leaves, depth;
    rt_bvh_stats(b, &nodes, &leaves, &depth);
    CHECK_EQ_INT(nodes, 1);
    CHECK_EQ_INT(leaves, 3);
    CHECK_EQ_INT(rt_bvh_outside(b), 0); /* no box outgrows the others */
    static const struct {
        rt_ray ray;
        int hit;
        uint64_t nodes, spheres;
    } cases[] = {
        {{{0, 50, -10}, {0, 0, 1}}, 0, 1, 0},   /* misses every box: the root only */
        {{{0, 0, -10}, {0, 0, 1}}, 1, 1, 1},    /* enters the box of {0} only */
        {{{100, 0, -10}, {0, 0, 1}}, 1, 1, 1},  /* enters the box of {100} only */
        {{{-10, 0, 0}, {1, 0, 0}}, 1, 1, 1},    /* hits 0 first: {100} and {200} pruned */
        {{{300, 0, 0}, {-1, 0, 0}}, 1, 1, 1},   /* hits 200 first: {100} and {0} pruned */
        {{{-10, 0.9, 0.9}, {1, 0, 0}}, 0, 1, 3}}; /* through every box, missing every sphere */
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        rt_bvh_counts c = {0, 0};
        rt_hit h;
        CHECK_EQ_INT(rt_bvh_closest_counted(b, &cases[i].ray, 0.001, INFINITY, &h, &c), cases[i].hit);
        CHECK_EQ_U64(c.nodes, cases[i].nodes);
        CHECK_EQ_U64(c.spheres, cases[i].spheres);
    }
    rt_bvh_free(b);
    rt_scene_free(&s);
}

/* The spheres the tree leaves out: a ground of radius 1000, then a sphere of
 * radius 200 whose box outgrows the small spheres', are tested before the
 * traversal (two sphere tests on every ray), and a hit on one bounds it; the
 * small spheres at x = 0, 3 and 6 stay in the tree: a root with the leaves
 * {0} and {3, 6}. */
static void check_outside(void)
{
    rt_scene s;
    grey_scene(&s);
    CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(0, 0, 0), 1.0, 0), RT_OK);
    CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(0, -1000, 0), 1000, 0), RT_OK);
    CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(3, 0, 0), 1.0, 0), RT_OK);
    CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(0, 0, 500), 200, 0), RT_OK);
    CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(6, 0, 0), 1.0, 0), RT_OK);
    rt_bvh *b;
    CHECK_EQ_INT(rt_bvh_build(&b, &s), RT_OK);
    CHECK_EQ_INT(rt_bvh_outside(b), 2);
    int nodes, leaves, depth;
    rt_bvh_stats(b, &nodes, &leaves, &depth);
    CHECK_EQ_INT(nodes, 1); /* three small spheres: one node */
    const struct {
        rt_ray ray;
        uint32_t prim; /* UINT32_MAX: a miss */
        double t;
        uint64_t spheres;
    } cases[] = {
        {{{50, 10, 0}, {0, -1, 0}}, 1, 1010 - sqrt(1000.0 * 1000 - 50 * 50), 2}, /* down onto the ground */
        {{{0, 10, 0}, {0, -1, 0}}, 0, 9, 3},          /* onto the small sphere 0: its leaf too */
        {{{0, 0, 100}, {0, 0, 1}}, 3, 200, 2},        /* into the radius-200 sphere */
        {{{0, 0, 1000}, {0, 0, -1}}, 3, 300, 2},      /* the radius-200 sphere first: leaf {0} pruned */
        {{{3, 10, 0}, {0, 1, 0}}, UINT32_MAX, 0, 2}}; /* up into the sky */
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        rt_bvh_counts c = {0, 0};
        rt_hit h = {0, 0};
        int hit = rt_bvh_closest_counted(b, &cases[i].ray, 0.001, INFINITY, &h, &c);
        CHECK_EQ_INT(hit, cases[i].prim != UINT32_MAX);
        if (hit) {
            CHECK_EQ_U64(h.prim, cases[i].prim);
            CHECK_NEAR(h.t, cases[i].t, 1e-12);
        }
        CHECK_EQ_U64(c.nodes, 1);
        CHECK_EQ_U64(c.spheres, cases[i].spheres);
    }
    rt_bvh_free(b);
    rt_scene_free(&s);
}

/* Outliers: a field of 64 spheres of radius 0.2 with one of radius 1 (five
 * times the median) and one of 0.7 (under four times): the first is tested
 * before the traversal though its box is far smaller than the field's, the
 * second stays in the tree; every ray's hit is still brute force's. */
static void check_outliers(void)
{
    rt_scene s;
    grey_scene(&s);
    for (int i = 0; i < 64; i++)
        CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(2.0 * (i % 8), 0.2, 2.0 * (i / 8)), 0.2, 0), RT_OK);
    CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(7, 1, 7), 1.0, 0), RT_OK);   /* index 64 */
    CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(3, 0.7, 11), 0.7, 0), RT_OK); /* index 65 */
    rt_bvh *b;
    CHECK_EQ_INT(rt_bvh_build(&b, &s), RT_OK);
    CHECK_EQ_INT(rt_bvh_outside(b), 1);
    rt_accel *brute;
    CHECK_EQ_INT(rt_accel_new(&brute, &s, RT_ACCEL_BRUTE), RT_OK);
    const rt_ray probes[] = {{{7, 10, 7}, {0, -1, 0}},  /* onto the outlier */
                             {{3, 10, 11}, {0, -1, 0}}, /* onto the sphere of 0.7 */
                             {{-5, 0.2, 0}, {1, 0, 0}}, /* along the first row */
                             {{-5, 1, 7}, {1, 0, 0}}};  /* past the field into the outlier */
    const uint32_t expect[] = {64, 65, 0, 64};
    for (size_t i = 0; i < sizeof probes / sizeof probes[0]; i++) {
        rt_hit h = {0, 0}, hb = {0, 0};
        CHECK_EQ_INT(rt_bvh_closest(b, &probes[i], 0.001, INFINITY, &h), 1);
        CHECK_EQ_INT(rt_accel_closest(brute, &probes[i], 0.001, INFINITY, &hb), 1);
        CHECK_EQ_U64(h.prim, expect[i]);
        CHECK_EQ_U64(hb.prim, expect[i]);
        CHECK(h.t == hb.t);
    }
    rt_accel_free(brute);
    rt_bvh_free(b);
    rt_scene_free(&s);
}

int main(void)
{
    rt_rng rng = rt_rng_for_stream(2024, RT_STREAM_TEST);
    for (int scene_i = 0; scene_i < 24; scene_i++) {
        rt_scene s;
        if (scene_i % 3 == 0) {
            CHECK_EQ_INT(rt_scene_build_final(&s, (uint64_t)scene_i, 1 + scene_i), RT_OK);
        } else {
            grey_scene(&s);
            int n = 1 + (int)(rt_rng_double(&rng) * (scene_i % 2 ? 3000 : 40));
            double spread = 1 + 50 * rt_rng_double(&rng);
            for (int i = 0; i < n; i++) {
                rt_vec3 c = rt_v3(spread * (2 * rt_rng_double(&rng) - 1), spread * (2 * rt_rng_double(&rng) - 1),
                                  spread * (2 * rt_rng_double(&rng) - 1));
                double r = rt_rng_double(&rng) < 0.02 ? 100 * rt_rng_double(&rng) + 0.01
                                                      : 0.001 + rt_rng_double(&rng) * spread * 0.1;
                if (rt_rng_double(&rng) < 0.1)
                    r = -r; /* hollow */
                CHECK_EQ_INT(rt_scene_add_sphere(&s, c, r, 0), RT_OK);
                /* In some scenes, clusters of twins: exact ties across
                 * leaves with equal boxes, which the lower index must win
                 * in whatever order a traversal or a packet meets them. */
                if (scene_i % 3 == 2 && rt_rng_double(&rng) < 0.05)
                    for (int twin = 0; twin < 11; twin++)
                        CHECK_EQ_INT(rt_scene_add_sphere(&s, c, r, 0), RT_OK);
            }
        }
        rt_accel *all[N_BOX_TESTS], *brute;
        for (int k = 0; k < N_BOX_TESTS; k++)
            CHECK_EQ_INT(rt_accel_new(&all[k], &s, box_tests[k]), RT_OK);
        rt_accel *bvh = all[0];
        CHECK_EQ_INT(rt_accel_new(&brute, &s, RT_ACCEL_BRUTE), RT_OK);
        CHECK(rt_accel_bvh(bvh) != NULL && rt_accel_bvh(brute) == NULL);
        int outside = rt_bvh_outside(rt_accel_bvh(bvh));
        if (scene_i % 3 == 0) /* the ground, and from grid 2 on (when spheres of radius 0.2 are the median) the
                               * three spheres of radius 1 */
            CHECK_EQ_INT(outside, scene_i == 0 ? 1 : 4);
        else
            scenes_outside += outside > 0;
        double ext = 0;
        for (uint32_t i = 0; i < s.n_spheres; i++)
            ext = fmax(ext, fabs(s.spheres[i].center.x) + fabs(s.spheres[i].radius));
        ext = fmin(ext, 60);
        rt_ray batch[4];
        for (int k = 0; k < 4000; k++) {
            rt_ray ray;
            const rt_sphere *sp = &s.spheres[(uint32_t)(rt_rng_double(&rng) * s.n_spheres)];
            double R = fabs(sp->radius);
            switch (k % 4) {
            case 0: /* from anywhere around the scene */
                ray.orig = rt_v3(ext * (4 * rt_rng_double(&rng) - 2), ext * (4 * rt_rng_double(&rng) - 2),
                                 ext * (4 * rt_rng_double(&rng) - 2));
                ray.dir = rnd_dir(&rng);
                break;
            case 1: { /* from inside a sphere */
                rt_vec3 off = rnd_dir(&rng);
                ray.orig = rt_v3_add(sp->center, rt_v3_scale(rt_v3_unit(off), 0.9 * R * rt_rng_double(&rng)));
                ray.dir = rnd_dir(&rng);
                break;
            }
            case 2: { /* from a surface point, as a bounce does */
                rt_vec3 n = rt_v3_unit(rnd_dir(&rng));
                ray.orig = rt_v3_add(sp->center, rt_v3_scale(n, R));
                ray.dir = rnd_dir(&rng);
                break;
            }
            default: { /* grazing: tangent to a sphere */
                rt_vec3 n = rt_v3_unit(rnd_dir(&rng));
                rt_vec3 t = rt_v3_unit(rt_v3_cross(n, rnd_dir(&rng)));
                rt_vec3 p = rt_v3_add(sp->center, rt_v3_scale(n, R * (1 + 1e-9 * (rt_rng_double(&rng) - 0.5))));
                ray.orig = rt_v3_sub(p, rt_v3_scale(t, 3 * R + 1));
                ray.dir = rt_v3_scale(t, 0.5 + rt_rng_double(&rng));
                break;
            }
            }
            const double tmin = k % 8 < 4 ? 0.001 : 1e-9;
            compare((const rt_accel *const *)all, brute, &ray, tmin);
            /* Packets: of unrelated rays (the last four, of the same tmin;
             * one to four of them), and of eight rays around this one, as
             * a pixel's camera rays are. */
            batch[k % 4] = ray;
            if (k % 4 == 3)
                compare_packet(rt_accel_bvh(bvh), brute, batch, 1 + (k / 4) % 4, tmin);
            if (k % 4 == 0) {
                rt_ray bundle[8];
                double spread_o = ext * 1e-3 * rt_rng_double(&rng), spread_d = 0.05 * rt_rng_double(&rng);
                for (int j = 0; j < 8; j++) {
                    bundle[j].orig = rt_v3_add(ray.orig, rt_v3_scale(rt_v3_unit(rnd_dir(&rng)), spread_o));
                    bundle[j].dir = rt_v3_add(ray.dir, rt_v3_scale(rnd_dir(&rng), spread_d));
                }
                bundle[k % 3] = ray;
                compare_packet(rt_accel_bvh(bvh), brute, bundle, 8, tmin);
            }
        }
        { /* leaves of one sphere each, unless built with larger leaves */
            int nodes, leaves, depth;
            rt_bvh_stats(rt_accel_bvh(bvh), &nodes, &leaves, &depth);
            int in_tree = (int)s.n_spheres - outside;
#if LEAF_MAX_TEST > 1
            scenes_multi_leaves += leaves < in_tree;
#else
            CHECK_EQ_INT(leaves, in_tree);
#endif
        }
        if (scene_i == 0) { /* the structure built on its own, without the front end */
            int nodes, leaves, depth;
            rt_bvh *b;
            CHECK_EQ_INT(rt_bvh_build(&b, &s), RT_OK);
            rt_bvh_stats(b, &nodes, &leaves, &depth);
            CHECK(nodes >= 1 && leaves >= 1 && depth >= 1);
            rt_bvh_free(b);
        }
        for (int k = 0; k < N_BOX_TESTS; k++)
            rt_accel_free(all[k]);
        rt_accel_free(brute);
        rt_scene_free(&s);
    }
    /* Empty scene: nothing is hit. */
    rt_scene e;
    rt_scene_init(&e);
    rt_accel *eb;
    CHECK_EQ_INT(rt_accel_new(&eb, &e, RT_ACCEL_BVH), RT_OK);
    rt_ray ray = {rt_v3(0, 0, 0), rt_v3(1, 0, 0)};
    rt_hit h;
    CHECK_EQ_INT(rt_accel_closest(eb, &ray, 0.001, INFINITY, &h), 0);
#if LEAF_MAX_TEST > 1
    printf("leaves of up to %d spheres: %d scenes with leaves of several\n", LEAF_MAX_TEST, scenes_multi_leaves);
    CHECK(scenes_multi_leaves > 0);
    (void)check_counts; /* its tree is the one of one-sphere leaves */
#else
    check_counts(); /* its tree is the one of one-sphere leaves */
#endif
    check_outside();
    check_outliers();
    printf("%ld rays, %ld hits, %ld mismatches; counted: %" PRIu64 " nodes, %" PRIu64 " sphere tests; "
           "random scenes with spheres outside the tree: %d; box tests bvh (%s), bvh-sse, bvh-scalar; "
           "%ld more rays in packets (%s)\n",
           rays, hits, mismatches, counted.nodes, counted.spheres, scenes_outside, rt_accel_box_test(eb), packet_rays,
           rt_bvh_uses_avx(rt_accel_bvh(eb)) ? "avx packet traversal" : "one at a time");
    rt_accel_free(eb);
    CHECK(scenes_outside > 0);
    CHECK(counted.nodes >= (uint64_t)rays); /* every scene has a root */
    CHECK_EQ_INT(mismatches, 0);
    CHECK(hits > rays / 4);
    CHECK_DONE();
}
