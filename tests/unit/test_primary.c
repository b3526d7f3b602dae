/* test_primary.c - the camera rays' candidate lists (primary.h) must give
 * every camera ray the closest hit brute force gives it, sphere and t to the
 * bit: random scenes (the book's, clouds with hollow and very large spheres,
 * clusters of twins for exact ties) seen by random cameras (pinhole and wide
 * lenses, narrow and wide fields of view, the camera inside a sphere, images
 * from 1x1 up), with random rays and the extreme rays of each tile (pixel
 * jitter 0 and just under 1, lens samples on the rim of the lens). Renders
 * with the lists must be the same bits as without them, through the path
 * loop of the CPU (packets on AVX) and the baseline one. And the lists must
 * prune: on the book's scene a tile lists a few spheres, not the scene. */
#include <stdlib.h>
#include <string.h>

#include "core_internal.h"
#include "accel.h"
#include "check.h"
#include "primary.h"
#include "render.h"
#include "rng.h"
#include "status.h"

static long rays, listed_rays, hits, mismatches;
/* renders that use a list with a sphere, and how many differ with the lists
 * emptied; their middle pixels' samples where the middle tile lists a
 * sphere, and how many of those differ */
static int renders, emptied_differ, middles, emptied_sample_differ;

/* One ray of pixel (x, y): its list's answer against brute force's. */
static void check_ray(const rt_primary *p, const rt_accel *brute, uint32_t x, uint32_t y, const rt_ray *ray)
{
    rays++;
    uint32_t first;
    int32_t n = rt_primary_tile(p, x, y, &first);
    if (n < 0)
        return;
    listed_rays++;
    rt_hit a = {0, 0}, b = {0, 0};
    int ha = rt_primary_closest(p, first, n, ray, 0.001, INFINITY, &a);
    int hb = rt_accel_closest(brute, ray, 0.001, INFINITY, &b);
    hits += hb;
    if (ha == hb && (!ha || (a.t == b.t && a.prim == b.prim)))
        return;
    if (mismatches < 5)
        fprintf(stderr, "mismatch at pixel (%u, %u): list %d prim %u t %.17g / brute %d prim %u t %.17g\n", x, y, ha,
                a.prim, a.t, hb, b.prim, b.t);
    mismatches++;
}

static void random_scene(rt_scene *s, rt_rng *rng, int kind)
{
    rt_scene_init(s);
    rt_material m = {.kind = RT_MAT_LAMBERTIAN, .albedo = rt_v3(0.5, 0.5, 0.5), .fuzz = 0, .ior = 1};
    CHECK_EQ_INT(rt_scene_add_material(s, &m, NULL), RT_OK);
    int n = 1 + (int)(rt_rng_double(rng) * 300);
    double spread = 1 + 20 * rt_rng_double(rng);
    for (int i = 0; i < n; i++) {
        rt_vec3 c = rt_v3(spread * (2 * rt_rng_double(rng) - 1), spread * (2 * rt_rng_double(rng) - 1),
                          spread * (2 * rt_rng_double(rng) - 1));
        double r = rt_rng_double(rng) < 0.02 ? 100 * rt_rng_double(rng) + 0.01 : 0.001 + rt_rng_double(rng) * 0.2 * spread;
        if (rt_rng_double(rng) < 0.1)
            r = -r; /* hollow */
        CHECK_EQ_INT(rt_scene_add_sphere(s, c, r, 0), RT_OK);
        if (kind == 2 && rt_rng_double(rng) < 0.05) /* twins: exact ties */
            for (int twin = 0; twin < 5; twin++)
                CHECK_EQ_INT(rt_scene_add_sphere(s, c, r, 0), RT_OK);
    }
}

static void random_camera(rt_camera_desc *d, rt_rng *rng, int inside_sphere, const rt_scene *s)
{
    double R = 5 + 40 * rt_rng_double(rng);
    d->lookfrom = rt_v3(R * (2 * rt_rng_double(rng) - 1), R * (2 * rt_rng_double(rng) - 1),
                        R * (2 * rt_rng_double(rng) - 1));
    if (inside_sphere && s->n_spheres) /* at the centre of a sphere: every ray leaves it */
        d->lookfrom = s->spheres[(uint32_t)(rt_rng_double(rng) * s->n_spheres)].center;
    d->lookat = rt_v3(2 * rt_rng_double(rng) - 1, 2 * rt_rng_double(rng) - 1, 2 * rt_rng_double(rng) - 1);
    d->vup = rt_v3(0, 1, 0);
    d->vfov_deg = rt_rng_double(rng) < 0.3 ? 1 + 10 * rt_rng_double(rng) : 10 + 150 * rt_rng_double(rng);
    d->aperture = rt_rng_double(rng) < 0.25 ? 0.0 : 3 * rt_rng_double(rng) * rt_rng_double(rng);
    d->focus_dist = 0.2 + 40 * rt_rng_double(rng);
}

int main(void)
{
    rt_rng rng = rt_rng_for_stream(77, RT_STREAM_TEST);
    int scenes = 0;
    for (int scene_i = 0; scene_i < 40; scene_i++) {
        rt_scene s;
        if (scene_i % 4 == 0)
            CHECK_EQ_INT(rt_scene_build_final(&s, (uint64_t)scene_i, 1 + scene_i % 12), RT_OK);
        else
            random_scene(&s, &rng, scene_i % 4);
        if (scene_i % 8 != 0) /* the book's own camera on every second book scene */
            random_camera(&s.camera, &rng, scene_i % 5 == 1, &s);
        const uint32_t W = scene_i % 10 == 3 ? 1 : 1 + (uint32_t)(rt_rng_double(&rng) * 60);
        const uint32_t H = scene_i % 10 == 7 ? 1 : 1 + (uint32_t)(rt_rng_double(&rng) * 60);
        rt_camera cam;
        if (rt_camera_init(&cam, &s.camera, (double)W / H) != RT_OK) { /* a degenerate draw: vup along the view */
            rt_scene_free(&s);
            continue;
        }
        scenes++;
        rt_primary *p;
        CHECK_EQ_INT(rt_primary_build(&p, &s, &cam, W, H), RT_OK);
        rt_accel *brute;
        CHECK_EQ_INT(rt_accel_new(&brute, &s, RT_ACCEL_BRUTE), RT_OK);
        const double dw = W > 1 ? W - 1 : 1, dh = H > 1 ? H - 1 : 1;
        const double under1 = 0x1.fffffffffffffp-1; /* the largest jitter rt_rng_double draws */
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                for (int k = 0; k < 6; k++) { /* random rays of the pixel */
                    double a = 6.283185307179586 * rt_rng_double(&rng), rho = sqrt(rt_rng_double(&rng));
                    rt_ray ray = rt_camera_ray_lens(&cam, (x + rt_rng_double(&rng)) / dw,
                                            (H - 1 - y + rt_rng_double(&rng)) / dh, rho * cos(a), rho * sin(a));
                    check_ray(p, brute, x, y, &ray);
                }
                /* the pixel's corners, from the rim of the lens */
                for (int k = 0; k < 4; k++) {
                    double a = 6.283185307179586 * rt_rng_double(&rng);
                    rt_ray ray = rt_camera_ray_lens(&cam, (x + (k & 1 ? under1 : 0)) / dw,
                                            (H - 1 - y + (k & 2 ? under1 : 0)) / dh, under1 * cos(a), under1 * sin(a));
                    check_ray(p, brute, x, y, &ray);
                }
            }
        /* Whole renders, with and without the lists: the same bits. The
         * book's scenes only (bounces in the random clouds are long). */
        if (scene_i % 4 == 0 && W * H <= 1200) {
            rt_accel *bvh;
            CHECK_EQ_INT(rt_accel_new(&bvh, &s, RT_ACCEL_BVH), RT_OK);
            rt_job rp = {.width = W,
                         .height = H,
                         .samples = 9,
                         .max_depth = 8,
                         .seed = 5,
                         .diffuse = RT_DIFFUSE_LAMBERTIAN,
                         .sampler = RT_SAMPLER_RANDOM};
            rt_renderer with, without;
            CHECK_EQ_INT(rt_render_init(&with, &s, bvh, &rp), RT_OK);
            CHECK_EQ_INT(rt_render_init(&without, &s, bvh, &rp), RT_OK);
            with.primary = p;
            size_t len = (size_t)W * H * 3;
            int64_t *a = calloc(len, sizeof *a), *b = calloc(len, sizeof *b);
            uint64_t sa = rt_render_rows(&with, 0, H, 0, 9, a, 1);
            uint64_t sb = rt_render_rows(&without, 0, H, 0, 9, b, 1);
            CHECK_EQ_U64(sa, sb);
            CHECK(memcmp(a, b, len * sizeof *a) == 0);
            /* the baseline path loop, one sample at a time */
            int same = 1;
            for (uint32_t y = 0; y < H; y += 3)
                for (uint32_t x = 0; x < W; x += 2) {
                    uint64_t na = 0, nb = 0;
                    rt_vec3 ca = rt_render_sample(&with, x, y, 1, &na), cb = rt_render_sample(&without, x, y, 1, &nb);
                    same &= na == nb && memcmp(&ca, &cb, sizeof ca) == 0;
                }
            CHECK(same);
            /* ... and the renderer does consult the lists: with every list
             * emptied (each camera ray then misses), both path loops render
             * something else. */
            const uint32_t tiles = p->tiles.tiles_x * p->tiles.tiles_y;
            int32_t *saved = malloc(tiles * sizeof *saved);
            for (uint32_t t = 0; t < tiles; t++) {
                saved[t] = p->tiles.tile[t].n;
                p->tiles.tile[t].n = p->tiles.tile[t].n < 0 ? -1 : 0;
            }
            memset(a, 0, len * sizeof *a);
            rt_render_rows(&with, 0, H, 0, 9, a, 1);
            uint64_t nd = 0;
            rt_vec3 cd = rt_render_sample(&with, W / 2, H / 2, 1, &nd);
            uint64_t nw = 0;
            rt_vec3 cw = rt_render_sample(&without, W / 2, H / 2, 1, &nw);
            int any = 0; /* a list with a sphere: then the emptied lists must show */
            for (uint32_t t = 0; t < tiles; t++)
                any |= saved[t] > 0;
            if (any) {
                emptied_differ += memcmp(a, b, len * sizeof *a) != 0;
                renders++;
            }
            uint32_t f0;
            if (saved[rt_primary_tile(p, W / 2, H / 2, &f0) < 0 ? 0 : (H / 2 >> p->tiles.shift) * p->tiles.tiles_x +
                                                                        (W / 2 >> p->tiles.shift)] > 0) {
                emptied_sample_differ += nd != nw || memcmp(&cd, &cw, sizeof cd) != 0;
                middles++;
            }
            for (uint32_t t = 0; t < tiles; t++)
                p->tiles.tile[t].n = saved[t];
            free(saved);
            free(a);
            free(b);
            rt_accel_free(bvh);
        }
        rt_accel_free(brute);
        rt_primary_free(p);
        rt_scene_free(&s);
    }
    printf("%d scenes, %ld camera rays, %ld through lists, %ld hits, %ld mismatches\n", scenes, rays, listed_rays,
           hits, mismatches);
    CHECK_EQ_INT(mismatches, 0);
    CHECK(scenes >= 30);
    printf("with the lists emptied: %d of %d renders differ, and %d of %d middle pixels' samples\n", emptied_differ,
           renders, emptied_sample_differ, middles);
    CHECK(renders >= 4);
    CHECK_EQ_INT(emptied_differ, renders); /* the path loop of the CPU (packets on AVX) */
    CHECK(emptied_sample_differ >= 1);     /* rt_render_sample's (a middle ray may miss every listed sphere) */
    CHECK(listed_rays > rays / 2);
    CHECK(hits > listed_rays / 4);

    /* The book's scene at 600x400 with its own camera: lists on nearly
     * every tile, a few spheres each. */
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_final(&s, 42, 11), RT_OK);
    rt_camera cam;
    CHECK_EQ_INT(rt_camera_init(&cam, &s.camera, 1.5), RT_OK);
    rt_primary *p;
    CHECK_EQ_INT(rt_primary_build(&p, &s, &cam, 600, 400), RT_OK);
    uint32_t tiles, listed;
    size_t cand;
    rt_primary_stats(p, &tiles, &listed, &cand);
    printf("final scene, 600x400: %u tiles, %u with a list, %.2f spheres a list (of %u), %zu bytes\n", tiles, listed,
           listed ? (double)cand / listed : 0.0, s.n_spheres, rt_primary_bytes(p));
    CHECK_EQ_INT(tiles, 75 * 50);
    CHECK(listed >= tiles * 9 / 10);
    CHECK(cand <= (size_t)listed * 6);
    rt_primary_free(p);

    /* A large image: larger tiles, so that the lists stay small; random
     * pixels' rays still get brute force's hits. */
    const uint32_t BW = 5000, BH = 4000;
    CHECK_EQ_INT(rt_camera_init(&cam, &s.camera, (double)BW / BH), RT_OK);
    CHECK_EQ_INT(rt_primary_build(&p, &s, &cam, BW, BH), RT_OK);
    rt_primary_stats(p, &tiles, &listed, &cand);
    printf("final scene, %ux%u: tiles of %u pixels, %u tiles, %u with a list, %zu bytes\n", BW, BH, 1u << p->tiles.shift,
           tiles, listed, rt_primary_bytes(p));
    CHECK(tiles <= RT_TILES_MAX);
    CHECK_EQ_INT(1u << p->tiles.shift, 32); /* 157 x 125 tiles; of 16 pixels there would be 313 x 250 */
    CHECK(rt_primary_bytes(p) < 2u << 20);
    rt_accel *brute;
    CHECK_EQ_INT(rt_accel_new(&brute, &s, RT_ACCEL_BRUTE), RT_OK);
    long before = mismatches, listed_before = listed_rays;
    for (int k = 0; k < 20000; k++) {
        uint32_t x = (uint32_t)(rt_rng_double(&rng) * BW), y = (uint32_t)(rt_rng_double(&rng) * BH);
        double a = 6.283185307179586 * rt_rng_double(&rng), rho = sqrt(rt_rng_double(&rng));
        rt_ray ray = rt_camera_ray_lens(&cam, (x + rt_rng_double(&rng)) / (BW - 1),
                                        (BH - 1 - y + rt_rng_double(&rng)) / (BH - 1), rho * cos(a), rho * sin(a));
        check_ray(p, brute, x, y, &ray);
    }
    CHECK_EQ_INT(mismatches - before, 0);
    CHECK(listed_rays - listed_before > 19000);
    rt_accel_free(brute);
    rt_primary_free(p);
    rt_scene_free(&s);
    CHECK_DONE();
}
