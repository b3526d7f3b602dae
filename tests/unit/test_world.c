/* test_world.c - book 2's geometry: quads and boxes against closed forms,
 * moving spheres at their time, instances flattened exactly, the media's
 * spans and free flights (transmittance exp(-d L)), and the scene bytes'
 * round trip. The walks against brute force: test_world_query.c. */
#include <stdlib.h>
#include <string.h>

#include "accel.h"
#include "check.h"
#include "core_internal.h"
#include "detmath.h"
#include "fbox.h"
#include "hash.h"
#include "rng.h"
#include "scenes.h"
#include "status.h"
#include "texture.h"
#include "world.h"
#include "xform.h"

static rt_ray ray_of(rt_vec3 o, rt_vec3 d)
{
    rt_ray r = {o, d};
    return r;
}

/* A quad hit and missed at closed-form points. */
static void check_quad(void)
{
    rt_scene s;
    rt_scene_init(&s);
    uint32_t m;
    rt_material lam = rt_scene_lambertian(rt_v3(0.5, 0.5, 0.5));
    CHECK_EQ_INT(rt_scene_add_material(&s, &lam, &m), RT_OK);
    /* the unit square at z = -2, x and y in [1, 3] */
    CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(1, 1, -2), rt_v3(2, 0, 0), rt_v3(0, 2, 0), m, NULL), RT_OK);
    CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(0, 0, 0), rt_v3(1, 0, 0), rt_v3(2, 0, 0), m, NULL), RT_EINVAL);
    CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(0, 0, 0), rt_v3(NAN, 0, 0), rt_v3(0, 1, 0), m, NULL), RT_EINVAL);
    CHECK_EQ_INT(s.shapes.quads.n, 1);
    rt_world *w;
    CHECK_EQ_INT(rt_world_build(&w, &s, RT_WORLD_BVH, 0.0, 1.0), RT_OK);
    rt_whit h;
    rt_ray r = ray_of(rt_v3(2, 1.5, 0), rt_v3(0, 0, -2)); /* |dir| 2: t in units of it */
    CHECK_EQ_INT(rt_world_closest(w, &r, 0, 0.001, INFINITY, &h), 1);
    CHECK_NEAR(h.t, 1.0, 1e-15);
    CHECK_EQ_INT(h.kind, RT_SHAPE_QUAD);
    rt_surface rec;
    double u, v;
    rt_world_surface(w, &h, &r, 0, 1, &rec, &u, &v);
    CHECK_NEAR(u, 0.5, 1e-15);
    CHECK_NEAR(v, 0.25, 1e-15);
    CHECK_EQ_INT(rec.front_face, 1); /* u x v = +z faces the ray coming from +z */
    CHECK_NEAR(rec.normal.z, 1.0, 0);
    r = ray_of(rt_v3(3.01, 1.5, 0), rt_v3(0, 0, -1)); /* just outside an edge */
    CHECK_EQ_INT(rt_world_closest(w, &r, 0, 0.001, INFINITY, &h), 0);
    r = ray_of(rt_v3(2, 2, 0), rt_v3(0, 0, -1));
    CHECK_EQ_INT(rt_world_closest(w, &r, 0, 0.001, 1.5, &h), 0); /* beyond tmax */
    rt_world_free(w);
    rt_scene_free(&s);
}

/* A moving sphere is where its time puts it; its box holds both ends. */
static void check_mover(void)
{
    rt_scene s;
    rt_scene_init(&s);
    uint32_t m;
    rt_material lam = rt_scene_lambertian(rt_v3(0.5, 0.5, 0.5));
    CHECK_EQ_INT(rt_scene_add_material(&s, &lam, &m), RT_OK);
    CHECK_EQ_INT(rt_scene_add_mover(&s, rt_v3(0, 0, -5), rt_v3(4, 0, -5), 1, m, NULL), RT_OK);
    rt_world *w;
    for (int brute = 0; brute < 2; brute++) {
        CHECK_EQ_INT(rt_world_build(&w, &s, brute ? RT_WORLD_BRUTE : RT_WORLD_BVH, 0.0, 1.0), RT_OK);
        rt_whit h;
        rt_ray r = ray_of(rt_v3(3, 0, 0), rt_v3(0, 0, -1));
        CHECK_EQ_INT(rt_world_closest(w, &r, 0.0, 0.001, INFINITY, &h), 0); /* at time 0 it is at x = 0 */
        CHECK_EQ_INT(rt_world_closest(w, &r, 0.75, 0.001, INFINITY, &h), 1); /* centre at x = 3 */
        CHECK_NEAR(h.t, 4.0, 1e-12);
        CHECK_EQ_INT(h.kind, RT_SHAPE_MOVER);
        rt_world_free(w);
    }
    rt_scene_free(&s);
}

/* A rotated and moved box is the book's instance: its corners where the
 * book's rotate_y then translate put them. */
static void check_instance(void)
{
    rt_scene s;
    rt_scene_init(&s);
    uint32_t m;
    rt_material lam = rt_scene_lambertian(rt_v3(0.5, 0.5, 0.5));
    CHECK_EQ_INT(rt_scene_add_material(&s, &lam, &m), RT_OK);
    const rt_xform r = rt_xform_rotate_y(90), t = rt_xform_translate(rt_v3(10, 0, 0));
    const rt_xform x = rt_xform_then(&r, &t);
    CHECK_EQ_INT(rt_scene_add_box(&s, rt_v3(0, 0, 0), rt_v3(1, 2, 3), m, &x), RT_OK);
    CHECK_EQ_INT(s.shapes.quads.n, 6);
    /* rotate_y(90): x' = z, z' = -x; the far corner (1, 2, 3) -> (3, 2, -1) + (10, 0, 0) */
    double hi[3] = {-1e9, -1e9, -1e9}, lo[3] = {1e9, 1e9, 1e9};
    for (uint32_t i = 0; i < 6; i++) {
        const rt_quad *q = &s.shapes.quads.items[i];
        const rt_vec3 c[4] = {q->q, rt_v3_add(q->q, q->u), rt_v3_add(q->q, q->v),
                              rt_v3_add(rt_v3_add(q->q, q->u), q->v)};
        for (int k = 0; k < 4; k++) {
            const double p[3] = {c[k].x, c[k].y, c[k].z};
            for (int a = 0; a < 3; a++) {
                hi[a] = fmax(hi[a], p[a]);
                lo[a] = fmin(lo[a], p[a]);
            }
        }
    }
    CHECK_NEAR(lo[0], 10, 1e-12);
    CHECK_NEAR(hi[0], 13, 1e-12);
    CHECK_NEAR(lo[2], -1, 1e-12);
    CHECK_NEAR(hi[2], 0, 1e-12);
    CHECK_NEAR(hi[1], 2, 1e-12);
    /* each face's normal points out of the box */
    const rt_vec3 centre = rt_v3(11.5, 1, -0.5);
    for (uint32_t i = 0; i < 6; i++) {
        const rt_quad *q = &s.shapes.quads.items[i];
        const rt_vec3 mid = rt_v3_add(q->q, rt_v3_scale(rt_v3_add(q->u, q->v), 0.5));
        CHECK(rt_v3_dot(rt_v3_cross(q->u, q->v), rt_v3_sub(mid, centre)) > 0);
    }
    /* a sphere of a rotated instance keeps its (u, v) through a frame */
    CHECK_EQ_INT(rt_scene_add_sphere_x(&s, rt_v3(0, 0, 1), 1, m, &x), RT_OK);
    CHECK_EQ_INT(s.spheres[0].frame, 1);
    CHECK_NEAR(s.spheres[0].center.x, 11, 1e-12);
    CHECK_EQ_INT(rt_scene_add_sphere_x(&s, rt_v3(0, 0, 1), 1, m, &t), RT_OK); /* no rotation: no frame */
    CHECK_EQ_INT(s.spheres[1].frame, 0);
    rt_scene_free(&s);
}

/* A hull medium's span (clipped by the hull's planes) against its
 * definition: the first and last crossing of the line with the hull's
 * quads, by the book's quad test; the same bits, on cornell-smoke's two
 * rotated boxes (their quads face out) and on the first again with its
 * quads facing in, for lines through and around them. */
static int quads_span(const rt_scene *s, const rt_medium *m, const rt_ray *r, double *t0, double *t1)
{
    double lo = INFINITY, hi = -INFINITY;
    for (uint32_t i = m->first; i < m->first + m->count; i++) {
        const rt_quad *q = &s->media.hull.items[i];
        const rt_vec3 N = rt_v3_cross(q->u, q->v), n = rt_v3_unit(N), w = rt_v3_scale(N, 1.0 / rt_v3_dot(N, N));
        const double denom = rt_v3_dot(n, r->dir);
        if (fabs(denom) < 1e-8)
            continue;
        const double t = (rt_v3_dot(n, q->q) - rt_v3_dot(n, r->orig)) / denom;
        const rt_vec3 hp = rt_v3_sub(rt_ray_at(r, t), q->q);
        const double a = rt_v3_dot(hp, rt_v3_cross(q->v, w)), b = rt_v3_dot(hp, rt_v3_cross(w, q->u));
        if (a >= 0 && a <= 1 && b >= 0 && b <= 1) {
            lo = fmin(lo, t);
            hi = fmax(hi, t);
        }
    }
    *t0 = lo;
    *t1 = hi;
    return hi > lo;
}

static void check_hull_span(void)
{
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_named(&s, "cornell-smoke", 42, 11, NULL), RT_OK);
    CHECK_EQ_INT(s.media.media.n, 2);
    const rt_medium m0 = s.media.media.items[0];
    rt_quad in[6];
    CHECK_EQ_INT(m0.count, 6);
    for (uint32_t i = 0; i < 6; i++) { /* u and v swapped: the normal turns inward */
        const rt_quad q = s.media.hull.items[m0.first + i];
        in[i] = (rt_quad){.q = q.q, .u = q.v, .v = q.u};
    }
    CHECK_EQ_INT(rt_scene_add_medium_hull(&s, in, 6, m0.density, m0.material, NULL), RT_OK);
    rt_world *w;
    CHECK_EQ_INT(rt_world_build(&w, &s, RT_WORLD_BVH, 0.0, 1.0), RT_OK);
    rt_rng rng = rt_rng_for_stream(11, RT_STREAM_TEST);
    const int N = 50000;
    int hits = 0, same = 0;
    for (int i = 0; i < N; i++) {
        const rt_vec3 o = rt_v3(rt_rng_range(&rng, -50, 600), rt_rng_range(&rng, -50, 600),
                                rt_rng_range(&rng, -50, 600));
        rt_vec3 d = rt_v3_scale(rt_sample_unit_vector(&rng), rt_rng_range(&rng, 0.1, 2));
        if (i % 16 == 1) /* along the boxes' vertical faces */
            d = rt_v3(0, 1, 0);
        const rt_ray r = ray_of(o, d);
        const uint32_t k = (uint32_t)i % 3u;
        double a0 = 0, a1 = 0, b0 = 0, b1 = 0;
        const int ha = rt_world_medium_span(w, k, &r, &a0, &a1);
        const int hb = quads_span(&s, &s.media.media.items[k], &r, &b0, &b1);
        hits += hb;
        const int ok = ha == hb && (!ha || (a0 == b0 && a1 == b1));
        same += ok;
        if (!ok && same + 5 > i)
            fprintf(stderr, "  line %d: clipped %d (%.17g, %.17g), quads %d (%.17g, %.17g)\n", i, ha, a0, a1, hb, b0,
                    b1);
    }
    fprintf(stderr, "cornell-smoke hulls: %d lines, %d through a box, %d spans the same as the quads'\n", N, hits,
            same);
    CHECK_EQ_INT(same, N);
    CHECK(hits > N / 10);
    rt_world_free(w);
    rt_scene_free(&s);
}

/* The path loop's free flights: a camera ray along -z crosses a black
 * (albedo 0) medium of density d over a length L in front of a white
 * background, so a sample brings 1 when it is not scattered and 0 when
 * it is: the mean of many samples is the transmittance exp(-d L). Also
 * with the slab split into two overlapping media of half the density
 * each (the densities add). */
static void check_transmittance(int overlap)
{
    rt_scene s;
    rt_scene_init(&s);
    uint32_t iso;
    rt_material m = rt_scene_isotropic(rt_v3(0, 0, 0));
    CHECK_EQ_INT(rt_scene_add_material(&s, &m, &iso), RT_OK);
    const double d = 0.5;
    for (int k = 0; k < (overlap ? 2 : 1); k++)
        CHECK_EQ_INT(rt_scene_add_medium_box(&s, rt_v3(-100, -100, -3), rt_v3(100, 100, -1), overlap ? d / 2 : d,
                                             iso, NULL),
                     RT_OK);
    CHECK_EQ_INT(rt_scene_add_medium_box(&s, rt_v3(0, 0, 0), rt_v3(1, 1, 1), -1, iso, NULL), RT_EINVAL);
    CHECK_EQ_INT(rt_scene_add_medium_sphere(&s, rt_v3(0, 0, 0), 1, NAN, iso), RT_EINVAL);
    s.background_kind = RT_BACKGROUND_COLOR;
    s.background = rt_v3(1, 1, 1);
    s.camera = (rt_camera_desc){.lookfrom = rt_v3(0, 0, 0),
                                .lookat = rt_v3(0, 0, -1),
                                .vup = rt_v3(0, 1, 0),
                                .vfov_deg = 1e-3,
                                .focus_dist = 1.0,
                                .pixels = RT_PIXELS_BOOK2};
    rt_accel *a;
    CHECK_EQ_INT(rt_accel_new(&a, &s, RT_ACCEL_BVH), RT_OK);
    rt_renderer r;
    rt_job job = {.width = 1,
                  .height = 1,
                  .samples = 1,
                  .max_depth = 8,
                  .seed = 5,
                  .diffuse = RT_DIFFUSE_LAMBERTIAN,
                  .sampler = RT_SAMPLER_RANDOM};
    CHECK_EQ_INT(rt_render_init(&r, &s, a, &job), RT_OK);
    CHECK(r.world != NULL);
    const uint32_t N = 100000;
    double sum = 0;
    uint64_t segs = 0;
    for (uint32_t k = 0; k < N; k++)
        sum += rt_render_sample(&r, 0, 0, k, &segs).x;
    const double p = exp(-d * 2.0), se = sqrt(p * (1 - p) / N);
    fprintf(stderr, "slab d %.2f L 2%s: %.5f of the light through, exp(-1) = %.5f (se %.5f)\n", d,
            overlap ? " (two overlapping media)" : "", sum / N, p, se);
    CHECK(fabs(sum / N - p) < 4 * se);
    rt_accel_free(a);
    rt_scene_free(&s);
}

/* log, sin, exp(-x), 1 - exp(-x), atan and tan without libm, against
 * libm (relative errors). */
static void check_detmath(void)
{
    double worst_log = 0, worst_sin = 0, worst_exp = 0, worst_omx = 0, worst_atan = 0, worst_tan = 0;
    rt_rng rng = rt_rng_for_stream(5, RT_STREAM_TEST);
    for (int i = 0; i < 100000; i++) {
        const double x = exp(rt_rng_range(&rng, -700, 700));
        worst_log = fmax(worst_log, fabs(rt_det_log(x) - log(x)) / fmax(1.0, fabs(log(x))));
        const double a = rt_rng_range(&rng, -200, 200);
        worst_sin = fmax(worst_sin, fabs(rt_det_sin(a) - sin(a)));
        const double d = exp(rt_rng_range(&rng, -30, 6)); /* optical depths, 1e-13 to 400 */
        worst_exp = fmax(worst_exp, fabs(rt_det_exp_neg(d) - exp(-d)) / exp(-d));
        worst_omx = fmax(worst_omx, fabs(rt_det_one_minus_exp_neg(d) + expm1(-d)) / -expm1(-d));
        const double y = (rt_rng_double(&rng) < 0.5 ? -1 : 1) * exp(rt_rng_range(&rng, -20, 20));
        worst_atan = fmax(worst_atan, fabs(rt_det_atan(y) - atan(y)) / fabs(atan(y)));
        const double th = rt_rng_range(&rng, -1.5707, 1.5707);
        worst_tan = fmax(worst_tan, fabs(rt_det_tan(th) - tan(th)) / fmax(1e-300, fabs(tan(th))));
    }
    fprintf(stderr, "detmath worst relative errors: log %.2g sin %.2g exp(-x) %.2g 1-exp(-x) %.2g atan %.2g tan %.2g\n",
            worst_log, worst_sin, worst_exp, worst_omx, worst_atan, worst_tan);
    CHECK(worst_log < 1e-14);
    CHECK(worst_sin < 1e-7);
    CHECK(worst_exp < 1e-13); /* x - k ln 2 loses digits as k grows */
    CHECK(worst_omx < 1e-14);
    CHECK(worst_atan < 1e-14);
    CHECK(worst_tan < 1e-10); /* near pi/2 its cosine is a difference */
    CHECK_NEAR(rt_det_exp_neg(800.0), 0.0, 0);
    CHECK_NEAR(rt_det_atan(0.0), 0.0, 0);
    CHECK_NEAR(rt_det_log(1.0), 0.0, 0);
    CHECK(rt_det_log(0.0) == -INFINITY);
    CHECK_NEAR(rt_det_log(4.9406564584124654e-324), -744.44007192138122, 1e-12); /* subnormal */
}

/* Texture values: the checker's cells, the image's nearest texel, noise
 * tables that depend on the seed only. */
static void check_textures(void)
{
    rt_scene s;
    rt_scene_init(&s);
    uint32_t a, b, c, img, it, n;
    rt_texture ta = {.kind = RT_TEX_SOLID, .color = {1, 0, 0}}, tb = {.kind = RT_TEX_SOLID, .color = {0, 0, 1}};
    CHECK_EQ_INT(rt_scene_add_texture(&s, &ta, &a), RT_OK);
    CHECK_EQ_INT(rt_scene_add_texture(&s, &tb, &b), RT_OK);
    rt_texture tc = {.kind = RT_TEX_CHECKER, .scale = 0.5, .even = a, .odd = b};
    CHECK_EQ_INT(rt_scene_add_texture(&s, &tc, &c), RT_OK);
    rt_texture bad = {.kind = RT_TEX_CHECKER, .scale = 0.5, .even = a, .odd = 7}; /* not listed before */
    CHECK_EQ_INT(rt_scene_add_texture(&s, &bad, NULL), RT_EINVAL);
    const uint8_t px[2 * 2 * 3] = {10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120};
    CHECK_EQ_INT(rt_scene_add_image(&s, 2, 2, px, &img), RT_OK);
    rt_texture ti = {.kind = RT_TEX_IMAGE, .image = img};
    CHECK_EQ_INT(rt_scene_add_texture(&s, &ti, &it), RT_OK);
    rt_texture tn = {.kind = RT_TEX_NOISE, .color = {1, 1, 1}, .scale = 4, .mode = RT_NOISE_MARBLE};
    CHECK_EQ_INT(rt_scene_add_texture(&s, &tn, &n), RT_OK);
    rt_perlin p1, p2, p3;
    rt_perlin_init(&p1, 1);
    rt_perlin_init(&p2, 1);
    rt_perlin_init(&p3, 2);
    CHECK(memcmp(&p1, &p2, sizeof p1) == 0);
    CHECK(memcmp(&p1, &p3, sizeof p1) != 0);
    /* the gradients: the Perlin stream's numbers as z, y, x in turn, whatever the compiler (texture.c) */
    rt_rng pr = rt_rng_for_stream(1, RT_STREAM_PERLIN);
    int same = 0;
    for (int i = 0; i < RT_PERLIN_POINTS; i++) {
        rt_vec3 g;
        do
            g.z = rt_rng_range(&pr, -1, 1), g.y = rt_rng_range(&pr, -1, 1), g.x = rt_rng_range(&pr, -1, 1);
        while (!(rt_v3_len2(g) > 1e-6));
        const rt_vec3 u = rt_v3_unit(g);
        same += u.x == p1.vec[i].x && u.y == p1.vec[i].y && u.z == p1.vec[i].z;
    }
    CHECK_EQ_INT(same, RT_PERLIN_POINTS);
    /* cells of 0.5: (0.2, 0.2, 0.2) is cell (0, 0, 0), even; (0.7, 0.2, 0.2) odd; (-0.2, 0.2, 0.2) odd */
    CHECK_NEAR(rt_texture_value(&s, &p1, c, 0, 0, rt_v3(0.2, 0.2, 0.2)).x, 1, 0);
    CHECK_NEAR(rt_texture_value(&s, &p1, c, 0, 0, rt_v3(0.7, 0.2, 0.2)).z, 1, 0);
    CHECK_NEAR(rt_texture_value(&s, &p1, c, 0, 0, rt_v3(-0.2, 0.2, 0.2)).z, 1, 0);
    /* (u, v) = (0.9, 0.9): the top row (v flipped), right column: texel (1, 0) */
    const rt_vec3 tx = rt_texture_value(&s, &p1, it, 0.9, 0.9, rt_v3(0, 0, 0));
    CHECK_NEAR(tx.x, 40 / 255.0, 1e-15);
    CHECK_NEAR(rt_texture_value(&s, &p1, it, -5, -5, rt_v3(0, 0, 0)).x, 70 / 255.0, 1e-15); /* clamped */
    double lo = 1, hi = 0;
    rt_rng rng = rt_rng_for_stream(8, RT_STREAM_TEST);
    for (int i = 0; i < 10000; i++) {
        const rt_vec3 q = rt_v3(rt_rng_range(&rng, -5, 5), rt_rng_range(&rng, -5, 5), rt_rng_range(&rng, -5, 5));
        const double v = rt_texture_value(&s, &p1, n, 0, 0, q).x;
        lo = fmin(lo, v);
        hi = fmax(hi, v);
        CHECK(fabs(rt_perlin_noise(&p1, q)) <= 1.0);
    }
    CHECK(lo >= 0 && lo < 0.05 && hi <= 1 && hi > 0.95); /* marble: the full range of 0.5 (1 + sin) */
    rt_scene_free(&s);
}

/* Hostile bytes with a valid checksum (the checksum guards against
 * accidents, not against a crafted buffer): each of many single-byte
 * changes loads or is refused with RT_EFORMAT, never read out of bounds
 * (the sanitizer build runs this) or accepted with an index out of range. */
static void check_hostile_bytes(const uint8_t *b, size_t n, const char *name)
{
    uint8_t *m = malloc(n);
    rt_rng rng = rt_rng_for_stream(11, RT_STREAM_TEST);
    int loaded = 0, refused = 0, other = 0;
    for (int i = 0; i < 3000; i++) {
        memcpy(m, b, n);
        const size_t at = 8 + (size_t)(rt_rng_next(&rng) % (n - 16)); /* past the magic, before the checksum */
        m[at] = (uint8_t)rt_rng_next(&rng);
        if (i % 3 == 0) /* a count or an index set huge */
            m[at] = 0xff;
        const uint64_t h = rt_hash_bytes(RT_HASH_INIT, m, n - 8);
        for (int k = 0; k < 8; k++)
            m[n - 8 + k] = (uint8_t)(h >> (8 * k));
        rt_scene t;
        const int st = rt_scene_deserialize(&t, m, n);
        if (st == RT_OK) {
            loaded++;
            for (uint32_t q = 0; q < t.shapes.quads.n; q++) /* every index in range */
                if (t.shapes.quads.items[q].material >= t.n_materials)
                    other++;
            for (uint32_t k = 0; k < t.n_materials; k++)
                if (t.materials[k].texture > t.tex.textures.n)
                    other++;
            rt_scene_free(&t);
        } else if (st == RT_EFORMAT || st == RT_EVERSION) {
            refused++;
        } else {
            other++;
        }
    }
    fprintf(stderr, "%s: 3000 hostile byte changes: %d loaded, %d refused, %d otherwise\n", name, loaded, refused, other);
    CHECK_EQ_INT(other, 0);
    CHECK(refused > 100);
    free(m);
}

/* Every book-2 scene's bytes round-trip exactly; a flipped byte is refused. */
static void check_bytes(void)
{
    static const uint8_t earth[4 * 2 * 3] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24};
    const rt_scene_image img = {4, 2, earth};
    for (unsigned i = 0; i < rt_scenes_count(); i++) {
        const rt_scene_info *in = rt_scenes_info(i);
        if (in->book < 2)
            continue;
        rt_scene s, t;
        CHECK_EQ_INT(rt_scene_build_named(&s, in->name, 42, 11, &img), RT_OK);
        CHECK(rt_scene_is_book2(&s));
        uint8_t *b1, *b2;
        size_t n1, n2;
        CHECK_EQ_INT(rt_scene_serialize(&s, &b1, &n1), RT_OK);
        CHECK_EQ_INT(b1[8], 2); /* version 2 */
        CHECK_EQ_INT(rt_scene_deserialize(&t, b1, n1), RT_OK);
        CHECK_EQ_INT(rt_scene_serialize(&t, &b2, &n2), RT_OK);
        rt_scene_free(&t);
        { /* rank 0's own bytes: the same scene without the checksum's pass */
            uint8_t *b3;
            size_t n3;
            CHECK_EQ_INT(rt_scene_deserialize_own(&t, b1, n1), RT_OK);
            CHECK_EQ_INT(rt_scene_serialize(&t, &b3, &n3), RT_OK);
            CHECK(n3 == n1 && memcmp(b3, b1, n1) == 0);
            rt_scene_free(&t);
            free(b3);
        }
        if (!(n1 == n2 && memcmp(b1, b2, n1) == 0)) {
            size_t k = 0;
            while (k < n1 && k < n2 && b1[k] == b2[k])
                k++;
            fprintf(stderr, "  %s: %zu and %zu bytes, first difference at %zu\n", in->name, n1, n2, k);
        }
        CHECK(n1 == n2 && memcmp(b1, b2, n1) == 0);
        if (!strcmp(in->name, "cornell-smoke") || !strcmp(in->name, "earth") || !strcmp(in->name, "quads") ||
            !strcmp(in->name, "checkered-spheres"))
            check_hostile_bytes(b1, n1, in->name);
        b1[n1 / 2] ^= 1;
        CHECK_EQ_INT(rt_scene_deserialize(&t, b1, n1), RT_ECHECKSUM);
        CHECK_EQ_INT(rt_scene_deserialize(&t, b1, n1 - 9), RT_EFORMAT);
        free(b1);
        free(b2);
        rt_scene_free(&s);
        if (in->needs_earth)
            CHECK_EQ_INT(rt_scene_build_named(&s, in->name, 42, 11, NULL), RT_ENOFILE);
    }
}

#if RT_BVH_HAVE_AVX
static uint32_t bits_of(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* The AVX walk's ray set-up (fbox.h's fbox_mray8_set) against the scalar
 * one it replaces, to the bit in every lane: (float) of the origin and
 * minus safe_inv of the direction, for zeros, values under safe_inv's clamp
 * (either sign), a float overflow and ordinary values. */
__attribute__((target("avx"))) static void check_mray(void)
{
    const double v[] = {0.0, -0.0, 1e-31, -1e-31, 1e-40, -1e-300, 2.5, -3.75, 0.1, 1e39, -1e39};
    const int n = (int)(sizeof v / sizeof v[0]);
    for (int i = 0; i < n; i++) {
        const double o[3] = {v[i], v[(i + 1) % n], v[(i + 2) % n]}, d[3] = {v[(i + 3) % n], v[(i + 4) % n], v[i]};
        const rt_ray r = ray_of(rt_v3(o[0], o[1], o[2]), rt_v3(d[0], d[1], d[2]));
        fbox_mray8 m;
        fbox_mray8_set(&m, &r, 0.25f);
        const __m256 got[6] = {m.ox, m.oy, m.oz, m.nx, m.ny, m.nz};
        for (int a = 0; a < 6; a++) {
            float lane[8];
            _mm256_storeu_ps(lane, got[a]);
            const float want = a < 3 ? (float)o[a] : -safe_inv(d[a - 3]);
            for (int k = 0; k < 8; k++)
                CHECK_EQ_U64(bits_of(lane[k]), bits_of(want));
        }
    }
}
#endif

int main(void)
{
#if RT_BVH_HAVE_AVX
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx"))
        check_mray();
#endif
    check_quad();
    check_mover();
    check_instance();
    check_hull_span();
    check_transmittance(0);
    check_transmittance(1);
    check_detmath();
    check_textures();
    check_bytes();
    CHECK_DONE();
}
