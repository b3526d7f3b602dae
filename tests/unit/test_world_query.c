/* test_world_query.c - the world's queries against brute force, the oracle:
 * the wide tree with each box test and the flat test of every quad
 * (world_flat.c) find brute force's closest hit (kind, index and t to the
 * bit) and agree on what stands in front of a shape, on book 2's and
 * book 3's scenes and on quads made to tie. */
#include <math.h>
#include <stdio.h>

#include "accel.h"
#include "camera.h"
#include "bvh.h"
#include "check.h"
#include "core_internal.h"
#include "rng.h"
#include "scenes.h"
#include "status.h"
#include "world.h"

/* Each mode (the CPU's best, which in a small scene on a CPU with AVX-512
 * is the flat test; the SSE2 and the portable box tests; the flat test
 * whatever the size) finds brute force's hit (kind, index and t to the
 * bit) for random rays in book 2's and book 3's scenes. */
static void check_bvh_vs_brute(const char *name, rt_world_mode mode)
{
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_named(&s, name, 42, 11, NULL), RT_OK);
    rt_world *wb, *wf;
    CHECK_EQ_INT(rt_world_build(&wb, &s, mode, 0.0, 1.0), RT_OK);
    CHECK_EQ_INT(rt_world_build(&wf, &s, RT_WORLD_BRUTE, 0.0, 1.0), RT_OK);
    rt_accel *acc; /* the spheres' own BVH: the world's static spheres must give its hits */
    CHECK_EQ_INT(rt_accel_new(&acc, &s, RT_ACCEL_BVH), RT_OK);
    rt_rng rng = rt_rng_for_stream(9, RT_STREAM_TEST);
    int hits = 0, same = 0, spheres = 0, as_accel = 0;
    const int N = 20000;
    const rt_vec3 from = s.camera.lookfrom, at = s.camera.lookat;
    const double span = 0.6 * rt_v3_len(rt_v3_sub(from, at));
    for (int i = 0; i < N; i++) {
        /* origins inside and around the scene, any direction */
        rt_vec3 o = rt_v3_add(at, rt_v3(span * (rt_rng_double(&rng) - 0.5), span * (rt_rng_double(&rng) - 0.5),
                                        span * (rt_rng_double(&rng) - 0.5)));
        if (i % 4 == 0)
            o = from;
        rt_vec3 d = rt_sample_unit_vector(&rng);
        if (i % 16 == 1) /* axis-aligned rays: zero direction components */
            d = rt_v3(0, i % 32 == 1 ? -1 : 0, i % 32 == 1 ? 0 : 1);
        const rt_ray r = {o, d};
        const double time = rt_rng_double(&rng);
        rt_whit a = {0, 0, 0, 0}, b = {0, 0, 0, 0};
        const int ha = rt_world_closest(wb, &r, time, 0.001, INFINITY, &a);
        const int hb = rt_world_closest(wf, &r, time, 0.001, INFINITY, &b);
        hits += hb;
        same += ha == hb && (!ha || (a.t == b.t && a.kind == b.kind && a.index == b.index &&
                                     a.material == b.material && a.material == rt_world_material(wb, &a)));
        rt_hit sh; /* the sphere BVH's hit, which the world's must be unless a quad or mover is as near */
        const int hs = s.n_spheres && rt_accel_closest(acc, &r, 0.001, INFINITY, &sh);
        spheres += ha && a.kind == RT_SHAPE_SPHERE;
        as_accel += ha ? (a.kind == RT_SHAPE_SPHERE ? hs && sh.t == a.t && sh.prim == a.index : !hs || sh.t >= a.t)
                       : !hs;
        if (!(ha == hb && (!ha || (a.t == b.t && a.kind == b.kind && a.index == b.index))) && same + 5 > i)
            fprintf(stderr, "  %s ray %d: bvh %d (t %.17g kind %u index %u), brute %d (t %.17g kind %u index %u)\n",
                    name, i, ha, a.t, a.kind, a.index, hb, b.t, b.kind, b.index);
    }
    fprintf(stderr, "%s (mode %d, flat test of %u quads): %d rays, %d hit (%d static spheres), %d the same as brute "
            "force, %d as the spheres' BVH\n", name, (int)mode, rt_world_flat_quads(wb), N, hits, spheres, same,
            as_accel);
    CHECK_EQ_INT(same, N);
    CHECK_EQ_INT(as_accel, N);
    CHECK(hits > N / 20);
    rt_accel_free(acc);
    rt_world_free(wb);
    rt_world_free(wf);
    rt_scene_free(&s);
}

/* rt_world_occluded and rt_world_shape_t against rt_world_closest: the
 * closest shape's own t is the hit's, nothing stands in front of it, and
 * another shape is occluded exactly when the closest hit up to its t is
 * not that shape. */
static void check_occluded(const char *name, rt_world_mode mode)
{
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_named(&s, name, 42, 11, NULL), RT_OK);
    rt_world *w;
    CHECK_EQ_INT(rt_world_build(&w, &s, mode, 0.0, 1.0), RT_OK);
    rt_rng rng = rt_rng_for_stream(11, RT_STREAM_TEST);
    const uint32_t nq = s.shapes.quads.n, ns = nq + s.shapes.movers.n, n = ns + s.n_spheres;
    int agree = 0, blocked = 0;
    const int N = 5000;
    const double span = 0.6 * rt_v3_len(rt_v3_sub(s.camera.lookfrom, s.camera.lookat));
    for (int i = 0; i < N; i++) {
        const double dist = span * rt_rng_double(&rng);
        const rt_vec3 o = rt_v3_add(s.camera.lookat, rt_v3_scale(rt_sample_unit_vector(&rng), dist));
        const double time = rt_rng_double(&rng);
        const uint32_t item = (uint32_t)(rt_rng_double(&rng) * n);
        const uint32_t kind = item < nq ? RT_SHAPE_QUAD : item < ns ? RT_SHAPE_MOVER : RT_SHAPE_SPHERE;
        const uint32_t index = item < nq ? item : item < ns ? item - nq : item - ns;
        rt_vec3 to; /* a point of the shape (the mover's centre at the time) */
        if (item < nq) {
            const rt_quad *q = &s.shapes.quads.items[index];
            const double fu = rt_rng_double(&rng), fv = rt_rng_double(&rng);
            to = rt_v3_add(q->q, rt_v3_add(rt_v3_scale(q->u, fu), rt_v3_scale(q->v, fv)));
        } else if (item < ns) {
            const rt_mover *mv = &s.shapes.movers.items[index];
            to = rt_v3_add(mv->center0, rt_v3_scale(rt_v3_sub(mv->center1, mv->center0), time));
        } else {
            to = s.spheres[index].center;
        }
        const rt_ray r = {o, i % 2 ? rt_v3_sub(to, o) : rt_sample_unit_vector(&rng)};
        rt_whit h, c;
        double t = 0;
        int ok = 1;
        if (rt_world_closest(w, &r, time, 0.001, INFINITY, &h)) {
            ok &= rt_world_shape_t(w, h.kind, h.index, &r, time, 0.001, &t) && t == h.t;
            ok &= !rt_world_occluded(w, &r, time, 0.001, h.t, h.kind, h.index);
        }
        if (rt_world_shape_t(w, kind, index, &r, time, 0.001, &t)) {
            const int occ = rt_world_occluded(w, &r, time, 0.001, t, kind, index);
            CHECK_EQ_INT(rt_world_closest(w, &r, time, 0.001, t, &c), 1);
            ok &= occ == !(c.kind == kind && c.index == index && c.t == t);
            blocked += occ;
        }
        agree += ok;
    }
    fprintf(stderr, "%s occluded (mode %d, flat test of %u quads): %d rays, %d agree with the closest hit, %d blocked\n",
            name, (int)mode, rt_world_flat_quads(w), N, agree, blocked);
    CHECK_EQ_INT(agree, N);
    CHECK(blocked > N / 50);
    rt_world_free(w);
    rt_scene_free(&s);
}

/* Quads that tie: the square z = -2, x and y in [0, 2], as items 0, 5 and
 * 17 (three registers of the flat test), with other quads about it. Every
 * mode finds brute force's hit; a ray through the square hits item 0 (of
 * equal t the lowest), which stands in front of its copies' hits but not
 * of its own. A ray in a quad's plane (zero denominator) and one whose
 * denominator is just below rt_quad_t's 1e-8 hit nothing there. */
static void check_ties(rt_world_mode mode)
{
    rt_scene s;
    rt_scene_init(&s);
    uint32_t m;
    rt_material lam = rt_scene_lambertian(rt_v3(0.5, 0.5, 0.5));
    CHECK_EQ_INT(rt_scene_add_material(&s, &lam, &m), RT_OK);
    rt_rng rng = rt_rng_for_stream(13, RT_STREAM_TEST);
    for (uint32_t i = 0; i < 20; i++) {
        rt_vec3 q = rt_v3(0, 0, -2), u = rt_v3(2, 0, 0), v = rt_v3(0, 2, 0);
        if (i != 0 && i != 5 && i != 17) { /* others: random, some sharing the square's plane or edges */
            q = rt_v3(4 * rt_rng_double(&rng) - 2, 4 * rt_rng_double(&rng) - 2, i % 3 ? -3 * rt_rng_double(&rng) : -2);
            u = i % 4 ? rt_v3(1 + rt_rng_double(&rng), 0, 0) : rt_sample_unit_vector(&rng);
            v = i % 4 ? rt_v3(0, 1 + rt_rng_double(&rng), 0) : rt_v3_cross(u, rt_sample_unit_vector(&rng));
        }
        CHECK_EQ_INT(rt_scene_add_quad(&s, q, u, v, m, NULL), RT_OK);
    }
    CHECK_EQ_INT(s.shapes.quads.n, 20);
    rt_world *w, *b;
    CHECK_EQ_INT(rt_world_build(&w, &s, mode, 0.0, 1.0), RT_OK);
    CHECK_EQ_INT(rt_world_build(&b, &s, RT_WORLD_BRUTE, 0.0, 1.0), RT_OK);
    int same = 0, square = 0;
    const int N = 20000;
    for (int i = 0; i < N; i++) {
        const rt_vec3 o = rt_v3(6 * rt_rng_double(&rng) - 3, 6 * rt_rng_double(&rng) - 3, 2 * rt_rng_double(&rng));
        const rt_vec3 to = rt_v3(2.2 * rt_rng_double(&rng) - 0.1, 2.2 * rt_rng_double(&rng) - 0.1, -2);
        const rt_ray r = {o, i % 8 ? rt_v3_sub(to, o) : rt_sample_unit_vector(&rng)};
        rt_whit a = {0, 0, 0, 0}, c = {0, 0, 0, 0};
        const int ha = rt_world_closest(w, &r, 0, 0.001, INFINITY, &a), hc = rt_world_closest(b, &r, 0, 0.001, INFINITY, &c);
        same += ha == hc && (!ha || (a.t == c.t && a.kind == c.kind && a.index == c.index));
        if (ha && a.index == 0) {
            square++;
            CHECK_EQ_INT(rt_world_occluded(w, &r, 0, 0.001, a.t, RT_SHAPE_QUAD, 5), 1);
            CHECK_EQ_INT(rt_world_occluded(w, &r, 0, 0.001, a.t, RT_SHAPE_QUAD, 17), 1);
            CHECK_EQ_INT(rt_world_occluded(w, &r, 0, 0.001, a.t, RT_SHAPE_QUAD, 0), 0);
        }
    }
    fprintf(stderr, "ties (mode %d, flat test of %u quads): %d rays, %d the same as brute force, %d hit the square\n",
            (int)mode, rt_world_flat_quads(w), N, same, square);
    CHECK_EQ_INT(same, N);
    CHECK(square > N / 10);
    rt_world_free(w);
    rt_world_free(b);
    rt_scene_free(&s);
    /* the square alone: a ray in its plane, and one that meets it at t
     * 1.11 inside but whose denominator is below 1e-8, hit nothing */
    rt_scene_init(&s);
    CHECK_EQ_INT(rt_scene_add_material(&s, &lam, &m), RT_OK);
    CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(0, 0, -2), rt_v3(2, 0, 0), rt_v3(0, 2, 0), m, NULL), RT_OK);
    CHECK_EQ_INT(rt_world_build(&w, &s, mode, 0.0, 1.0), RT_OK);
    rt_whit h;
    const rt_ray in_plane = {rt_v3(-1, 1, -2), rt_v3(1, 0, 0)};
    CHECK_EQ_INT(rt_world_closest(w, &in_plane, 0, 0.001, INFINITY, &h), 0);
    const rt_ray grazing = {rt_v3(0.5, 1, -1.99999999), rt_v3(1, 0, -0.9e-8)};
    CHECK_EQ_INT(rt_world_closest(w, &grazing, 0, 0.001, INFINITY, &h), 0);
    const rt_ray steeper = {rt_v3(0.5, 1, -1.99999999), rt_v3(1, 0, -1.1e-8)}; /* above 1e-8: a hit */
    CHECK_EQ_INT(rt_world_closest(w, &steeper, 0, 0.001, INFINITY, &h), 1);
    rt_world_free(w);
    rt_scene_free(&s);
}

/* A glass sphere's room (world_rooms.c): rays from inside it, and from
 * its surface either way, get brute force's hit from
 * rt_world_closest_from (and from outside it, the walk's), whatever pokes into the ball (a sphere, a hollow
 * inner sphere, a quad through it, a moving sphere at some times) or stands
 * just beyond it (a quad 0.001 past its pole); the hollow sphere is a room
 * of its own. A third glass sphere with nine shapes in it gets no room,
 * the walk answers. */
static void check_rooms(rt_world_mode mode)
{
    rt_scene s;
    rt_scene_init(&s);
    uint32_t lam, glass;
    const rt_material ml = rt_scene_lambertian(rt_v3(0.5, 0.5, 0.5)), mg = rt_scene_dielectric(1.5);
    CHECK_EQ_INT(rt_scene_add_material(&s, &ml, &lam), RT_OK);
    CHECK_EQ_INT(rt_scene_add_material(&s, &mg, &glass), RT_OK);
    CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(0, 0, 0), 1.0, glass), RT_OK); /* sphere 0: the room */
    CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(0.9, 0, 0), 0.3, lam), RT_OK);
    CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(0, 0.5, 0), -0.2, glass), RT_OK);
    CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(5, 0, 0), 1.0, glass), RT_OK); /* sphere 3: too crowded */
    for (int i = 0; i < 9; i++)
        CHECK_EQ_INT(rt_scene_add_sphere(&s, rt_v3(5 + 0.8 * cos(i), 0.8 * sin(i), 0), 0.1, lam), RT_OK);
    CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(-2, -0.5, -2), rt_v3(4, 0, 0), rt_v3(0, 0, 4), lam, NULL), RT_OK);
    CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3(-1, -1, 1.001), rt_v3(2, 0, 0), rt_v3(0, 2, 0), lam, NULL), RT_OK);
    CHECK_EQ_INT(rt_scene_add_mover(&s, rt_v3(0, 0, 1.2), rt_v3(0, 0, 0.8), 0.25, lam, NULL), RT_OK);
    rt_world *w, *b;
    CHECK_EQ_INT(rt_world_build(&w, &s, mode, 0.0, 1.0), RT_OK);
    CHECK_EQ_INT(rt_world_build(&b, &s, RT_WORLD_BRUTE, 0.0, 1.0), RT_OK);
    CHECK_EQ_INT(rt_world_rooms(w), 2);
    CHECK_EQ_INT(rt_world_rooms(b), 0);
    rt_rng rng = rt_rng_for_stream(17, RT_STREAM_TEST);
    int same = 0, near = 0, far_side = 0;
    const int N = 40000;
    for (int i = 0; i < N; i++) {
        const uint32_t room = i % 2 ? 0 : i % 3 ? 3 : 2;
        const rt_vec3 c = room == 3 ? rt_v3(5, 0, 0) : room == 2 ? rt_v3(0, 0.5, 0) : rt_v3(0, 0, 0);
        const double radius = room == 2 ? 0.2 : 1.0;
        rt_vec3 o = rt_v3_add(c, rt_v3_scale(rt_sample_unit_vector(&rng), radius)); /* on the surface, rounded */
        if (i % 4 == 1) /* inside */
            o = rt_v3_add(c, rt_v3_scale(rt_sample_unit_vector(&rng), radius * rt_rng_double(&rng)));
        if (i % 8 == 5) /* outside (a path's flight in a medium about the sphere): the walk's answer */
            o = rt_v3_add(c, rt_v3_scale(rt_sample_unit_vector(&rng), radius * (1.01 + 2 * rt_rng_double(&rng))));
        if (i % 8 == 3) { /* where a ray from outside meets the sphere */
            const rt_vec3 at = rt_v3_add(c, rt_v3_scale(rt_sample_unit_vector(&rng), 3.0 * radius));
            const rt_ray in = {at,
                               rt_v3_sub(rt_v3_add(c, rt_v3_scale(rt_sample_unit_vector(&rng), 0.5 * radius)), at)};
            double t;
            if (rt_world_shape_t(b, RT_SHAPE_SPHERE, room, &in, 0.0, 0.001, &t))
                o = rt_ray_at(&in, t);
        }
        const rt_ray r = {o, rt_v3_scale(rt_sample_unit_vector(&rng), 0.5 + rt_rng_double(&rng))};
        const double time = rt_rng_double(&rng);
        const rt_whit from = {1.0, RT_SHAPE_SPHERE, room, glass};
        rt_whit a = {0, 0, 0, 0}, e = {0, 0, 0, 0};
        const int ha = rt_world_closest_from(w, &r, time, 0.001, INFINITY, &from, &a);
        const int he = rt_world_closest(b, &r, time, 0.001, INFINITY, &e);
        same += ha == he && (!ha || (a.t == e.t && a.kind == e.kind && a.index == e.index && a.material == e.material));
        near += room == 0 && he && !(e.kind == RT_SHAPE_SPHERE && e.index == 0) &&
                rt_v3_len(rt_v3_sub(rt_ray_at(&r, e.t), c)) < 1.0;
        far_side += room == 0 && he && e.kind == RT_SHAPE_SPHERE && e.index == 0;
        if (!(ha == he && (!ha || (a.t == e.t && a.kind == e.kind && a.index == e.index))) && same + 5 > i)
            fprintf(stderr, "  room ray %d: %d (t %.17g kind %u index %u), brute %d (t %.17g kind %u index %u)\n", i,
                    ha, a.t, a.kind, a.index, he, e.t, e.kind, e.index);
    }
    fprintf(stderr, "rooms (mode %d): %d rays from glass spheres, %d the same as brute force, %d hit something "
            "inside the room, %d its far side\n", (int)mode, N, same, near, far_side);
    CHECK_EQ_INT(same, N);
    CHECK(near > N / 40);
    CHECK(far_side > N / 10);
    rt_world_free(w);
    rt_world_free(b);
    rt_scene_free(&s);
}

/* The camera rays' lists (world_lists.c): camera rays made as path2.c's
 * start2 makes them (its pixel mapping, jitter in [0, 1) up to its ends,
 * the lens's disk up to its rim, any time) get brute force's hit from their
 * tile's list, on scenes with and without a lens, the book-1 pixel mapping
 * too; a quarter of the rays at least come from lists. */
static void check_lists_of(const char *name, rt_scene s, uint32_t W, uint32_t H)
{
    rt_camera cam;
    CHECK_EQ_INT(rt_camera_init(&cam, &s.camera, (double)W / H), RT_OK);
    rt_world *w, *b;
    CHECK_EQ_INT(rt_world_build(&w, &s, RT_WORLD_BVH, 0.0, 1.0), RT_OK);
    CHECK_EQ_INT(rt_world_build(&b, &s, RT_WORLD_BRUTE, 0.0, 1.0), RT_OK);
    rt_world_lists *l;
    CHECK_EQ_INT(rt_world_lists_build(&l, w, &cam, s.camera.pixels == RT_PIXELS_BOOK2, W, H), RT_OK);
    rt_rng rng = rt_rng_for_stream(19, RT_STREAM_TEST);
    int same = 0, listed = 0, hits = 0;
    const int N = 40000;
    for (int i = 0; i < N; i++) {
        uint32_t x = (uint32_t)(rt_rng_next(&rng) % W), y = (uint32_t)(rt_rng_next(&rng) % H);
        if (i % 3 == 0) /* a tile's edge */
            x = (x & ~7u) + (i % 2 ? 0 : 7 < W - 1 - (x & ~7u) ? 7 : W - 1 - (x & ~7u));
        const double ends[3] = {0.0, 0x1.fffffffffffffp-1, 0.5};
        const double du = i % 7 < 3 ? ends[i % 7] : rt_rng_double(&rng);
        const double dv = i % 5 < 3 ? ends[i % 5] : rt_rng_double(&rng);
        double u, v; /* start2's mapping */
        if (s.camera.pixels == RT_PIXELS_BOOK2) {
            u = ((double)x + du) / (double)W;
            v = 1.0 - ((double)y + dv) / (double)H;
        } else {
            u = ((double)x + du) / (double)(W > 1 ? W - 1 : 1);
            v = ((double)(H - 1 - y) + dv) / (double)(H > 1 ? H - 1 : 1);
        }
        rt_vec3 d = rt_sample_unit_vector(&rng); /* on the lens's rim, or inside */
        d = rt_v3_scale(rt_v3_unit(rt_v3(d.x, d.y, 0)), i % 3 ? rt_rng_double(&rng) : 1.0);
        const rt_ray r = rt_camera_ray_lens(&cam, u, v, d.x, d.y);
        const double time = rt_rng_double(&rng);
        uint32_t first;
        const int32_t n = rt_world_lists_tile(l, x, y, &first);
        rt_whit a = {0, 0, 0, 0}, e = {0, 0, 0, 0};
        const int he = rt_world_closest(b, &r, time, 0.001, INFINITY, &e);
        const int ha = n >= 0 ? rt_world_closest_listed(w, l, first, n, &r, time, 0.001, INFINITY, &a) : he;
        if (n < 0)
            a = e;
        listed += n >= 0;
        hits += he;
        same += ha == he && (!ha || (a.t == e.t && a.kind == e.kind && a.index == e.index && a.material == e.material));
        if (!(ha == he && (!ha || (a.t == e.t && a.kind == e.kind && a.index == e.index))) && same + 5 > i)
            fprintf(stderr, "  %s camera ray %d (pixel %u, %u): list %d (t %.17g kind %u index %u), brute %d (t %.17g "
                    "kind %u index %u)\n", name, i, x, y, ha, a.t, a.kind, a.index, he, e.t, e.kind, e.index);
    }
    uint32_t tiles, with;
    size_t cands;
    rt_world_lists_stats(l, &tiles, &with, &cands);
    fprintf(stderr, "%s lists (%ux%u, book-%d pixels, lens %g): %u of %u tiles listed, %zu items; %d camera rays, %d "
            "from lists, %d hit, %d the same as brute force\n", name, W, H, s.camera.pixels == RT_PIXELS_BOOK2 ? 2 : 1,
            cam.lens_radius, with, tiles, cands, N, listed, hits, same);
    CHECK_EQ_INT(same, N);
    CHECK(listed > N / 4);
    rt_world_lists_free(l);
    rt_world_free(w);
    rt_world_free(b);
    rt_scene_free(&s);
}

static void check_lists(const char *name, uint32_t W, uint32_t H, int book1_pixels)
{
    rt_scene s;
    static const uint8_t earth[4 * 2 * 3] = {10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120,
                                             130, 140, 150, 160, 170, 180, 190, 200, 210, 220, 230, 240};
    const rt_scene_image img = {4, 2, earth};
    CHECK_EQ_INT(rt_scene_build_named(&s, name, 42, 11, &img), RT_OK);
    if (book1_pixels)
        s.camera.pixels = RT_PIXELS_SEED;
    check_lists_of(name, s, W, H);
}

/* Shapes smaller than a pixel (spheres of a quarter pixel, slivers of
 * quads, moving spheres), 720 of them in view, so that a list that missed
 * a tile's edge by a fraction of a pixel would lose some: the pinhole with
 * book 2's pixels, and a lens (out of focus before and behind) with book
 * 1's. */
static void check_lists_tiny(int lens)
{
    rt_scene s;
    rt_scene_init(&s);
    uint32_t m;
    const rt_material lam = rt_scene_lambertian(rt_v3(0.5, 0.5, 0.5));
    CHECK_EQ_INT(rt_scene_add_material(&s, &lam, &m), RT_OK);
    rt_rng rng = rt_rng_for_stream(23, RT_STREAM_TEST);
    for (int i = 0; i < 240; i++) {
        const double z = 8 * rt_rng_double(&rng), k = (10 + z) / 10; /* the view's size grows with the depth */
        const rt_vec3 c = rt_v3(k * (9 * rt_rng_double(&rng) - 4.5), k * (7 * rt_rng_double(&rng) - 3.5), z);
        CHECK_EQ_INT(rt_scene_add_sphere(&s, c, 0.08, m), RT_OK);
        CHECK_EQ_INT(rt_scene_add_quad(&s, rt_v3_add(c, rt_v3(0.2, 0, 0)), rt_v3(0.01, 0, 0), rt_v3(0, 0.3, 0.05), m,
                                       NULL),
                     RT_OK);
        CHECK_EQ_INT(rt_scene_add_mover(&s, rt_v3_add(c, rt_v3(0, 0.2, 0)), rt_v3_add(c, rt_v3(0.1, 0.2, 0)), 0.05, m,
                                        NULL),
                     RT_OK);
    }
    s.camera = (rt_camera_desc){rt_v3(0, 0, -10), rt_v3(0, 0, 0), rt_v3(0, 1, 0), 40, lens ? 1.0 : 0.0, 10.0,
                                lens ? RT_PIXELS_SEED : RT_PIXELS_BOOK2};
    check_lists_of(lens ? "tiny shapes, lens" : "tiny shapes", s, 64, 48);
}

int main(void)
{
    const rt_world_mode modes[] = {RT_WORLD_BVH, RT_WORLD_BVH_SSE, RT_WORLD_BVH_SCALAR, RT_WORLD_FLAT};
    for (int k = 0; k < 4; k++) {
        check_bvh_vs_brute("cornell-box", modes[k]);
        check_bvh_vs_brute("cornell-smoke", modes[k]);
        check_bvh_vs_brute("book3-final", modes[k]);
        check_bvh_vs_brute("simple-light", modes[k]);
        check_bvh_vs_brute("bouncing-spheres", modes[k]);
        check_bvh_vs_brute("quads", modes[k]);
        check_occluded("cornell-box", modes[k]);
        check_occluded("book3-final", modes[k]);
        check_occluded("bouncing-spheres", modes[k]);
        check_ties(modes[k]);
        check_rooms(modes[k]);
    }
    check_occluded("cornell-smoke", RT_WORLD_BRUTE);
    const char *listed[] = {"book2-final", "cornell-box", "book3-final", "bouncing-spheres", "quads", "simple-light",
                            "cornell-smoke", "checkered-spheres", "perlin-spheres"};
    for (int k = 0; k < 9; k++)
        check_lists(listed[k], 64, 48, 0);
    check_lists("book2-final", 200, 200, 0);
    check_lists("quads", 40, 30, 1);
    check_lists_tiny(0);
    check_lists_tiny(1);
    /* which scenes the CPU's best mode tests flat (world_flat.c's rule) */
    rt_scene s;
    rt_world *w;
    __builtin_cpu_init();
    const uint32_t avx512 = __builtin_cpu_supports("avx512f") && RT_BVH_HAVE_AVX;
    /* the rooms of few quads; not cornell-box's 18 quads, nor scenes of
     * objects apart (quads, simple-light: about one leaf a ray) */
    const char *names[] = {"book3-final", "cornell-smoke", "cornell-box", "quads", "simple-light", "bouncing-spheres"};
    const uint32_t flat[] = {12, 6, 0, 0, 0, 0};
    for (int k = 0; k < 6; k++) {
        CHECK_EQ_INT(rt_scene_build_named(&s, names[k], 42, 11, NULL), RT_OK);
        CHECK_EQ_INT(rt_world_build(&w, &s, RT_WORLD_BVH, 0.0, 1.0), RT_OK);
        CHECK_EQ_INT(rt_world_flat_quads(w), avx512 * flat[k]);
        rt_world_free(w);
        rt_scene_free(&s);
    }
    fprintf(stderr, "this CPU %s AVX-512: the flat test %s\n", avx512 ? "has" : "lacks",
            avx512 ? "ran above" : "was not tested");
    CHECK_DONE();
}
