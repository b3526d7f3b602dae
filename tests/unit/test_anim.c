/* test_anim.c - a frame's camera and shutter (anim.h): keyframes at and
 * between keys and held at the ends, the turntable on the scene's camera,
 * the shutter's intervals and defaults, keys through the byte format, and
 * moving spheres found at a later frame's time. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "accel.h"
#include "anim.h"
#include "check.h"
#include "core_internal.h"
#include "status.h"
#include "world.h"

static rt_camera_key key(double frame, rt_vec3 from, double vfov)
{
    return (rt_camera_key){.frame = frame, .lookfrom = from, .lookat = rt_v3(0, 0, 0), .vup = rt_v3(0, 1, 0),
                           .vfov_deg = vfov, .aperture = 0.0, .focus_dist = 10.0};
}

static int same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

static int same_view(const rt_camera_desc *d, const rt_camera_key *k)
{
    return same_bits(d->lookfrom.x, k->lookfrom.x) && same_bits(d->lookfrom.y, k->lookfrom.y) &&
           same_bits(d->lookfrom.z, k->lookfrom.z) && same_bits(d->vfov_deg, k->vfov_deg) &&
           same_bits(d->focus_dist, k->focus_dist) && same_bits(d->aperture, k->aperture);
}

/* Keys at frames 10 and 20 (and 40): exact at the keys, linear between,
 * held outside; the checks that keys must pass. */
static void test_keys(void)
{
    rt_scene s;
    rt_scene_init(&s);
    s.camera.pixels = RT_PIXELS_BOOK2;
    CHECK_EQ_INT(rt_anim_camera_animates(&s), 0);
    const rt_camera_key k[3] = {key(10, rt_v3(0.1, 2, 10), 20), key(20, rt_v3(10.3, 2, 0), 40),
                                key(40, rt_v3(0, 7, 10), 30)};
    for (int i = 0; i < 3; i++)
        CHECK_EQ_INT(rt_anim_add_key(&s, &k[i]), RT_OK);
    CHECK_EQ_INT(rt_anim_camera_animates(&s), 1);
    rt_camera_desc d;
    double t0, t1;
    CHECK_EQ_INT(rt_anim_frame(&s, NULL, 10, &d, &t0, &t1), RT_OK);
    CHECK_EQ_INT(same_view(&d, &k[0]), 1);
    CHECK_EQ_INT(d.pixels, RT_PIXELS_BOOK2); /* the scene camera's */
    CHECK_EQ_INT(rt_anim_frame(&s, NULL, 20, &d, &t0, &t1), RT_OK);
    CHECK_EQ_INT(same_view(&d, &k[1]), 1);
    CHECK_EQ_INT(rt_anim_frame(&s, NULL, 15, &d, &t0, &t1), RT_OK); /* halfway */
    CHECK_NEAR(d.lookfrom.x, 5.2, 1e-15);
    CHECK_NEAR(d.lookfrom.z, 5.0, 0);
    CHECK_NEAR(d.vfov_deg, 30.0, 0);
    CHECK_EQ_INT(rt_anim_frame(&s, NULL, 30, &d, &t0, &t1), RT_OK); /* halfway in the second span */
    CHECK_NEAR(d.lookfrom.y, 4.5, 0);
    CHECK_NEAR(d.vfov_deg, 35.0, 0);
    CHECK_EQ_INT(rt_anim_frame(&s, NULL, 12, &d, &t0, &t1), RT_OK);
    CHECK_NEAR(d.vfov_deg, 24.0, 1e-14);
    CHECK_EQ_INT(rt_anim_frame(&s, NULL, 0, &d, &t0, &t1), RT_OK); /* before the first: held */
    CHECK_EQ_INT(same_view(&d, &k[0]), 1);
    CHECK_EQ_INT(rt_anim_frame(&s, NULL, 1000, &d, &t0, &t1), RT_OK); /* after the last: held */
    CHECK_EQ_INT(same_view(&d, &k[2]), 1);
    rt_camera_key bad = key(40, rt_v3(1, 1, 1), 20); /* the last key's frame again */
    CHECK_EQ_INT(rt_anim_add_key(&s, &bad), RT_EINVAL);
    bad.frame = 39; /* before it */
    CHECK_EQ_INT(rt_anim_add_key(&s, &bad), RT_EINVAL);
    bad.frame = 50;
    bad.lookfrom.y = NAN;
    CHECK_EQ_INT(rt_anim_add_key(&s, &bad), RT_EINVAL);
    bad.lookfrom = rt_v3(0, 0, 0); /* = lookat */
    CHECK_EQ_INT(rt_anim_add_key(&s, &bad), RT_EINVAL);
    bad.lookfrom = rt_v3(0, 5, 0); /* along vup */
    CHECK_EQ_INT(rt_anim_add_key(&s, &bad), RT_EINVAL);
    bad.lookfrom = rt_v3(1, 5, 0);
    bad.frame = 4294967296.0;
    CHECK_EQ_INT(rt_anim_add_key(&s, &bad), RT_EINVAL);
    CHECK_EQ_INT(s.keys.n, 3);
    for (uint32_t i = 3; i < RT_SCENE_MAX_KEYS; i++) {
        rt_camera_key more = key(40 + i, rt_v3(1, 2, 3), 20);
        CHECK_EQ_INT(rt_anim_add_key(&s, &more) == RT_OK, 1);
    }
    rt_camera_key one_more = key(1e6, rt_v3(1, 2, 3), 20);
    CHECK_EQ_INT(rt_anim_add_key(&s, &one_more), RT_EOVERFLOW);
    rt_scene_free(&s);
}

/* The turntable orbits the scene's camera: frame 0 and whole turns are it,
 * to the bit; a quarter turn moves lookfrom a quarter about vup. */
static void test_turntable(void)
{
    rt_scene s;
    rt_scene_init(&s);
    s.camera.lookfrom = rt_v3(13, 2, 3);
    s.camera.lookat = rt_v3(0, 0, 0);
    s.camera.vfov_deg = 20;
    s.camera.focus_dist = 10;
    const rt_anim_opts a = {.turn_degrees = 360, .turn_frames = 48};
    rt_camera_desc d;
    double t0, t1;
    CHECK_EQ_INT(rt_anim_frame(&s, &a, 0, &d, &t0, &t1), RT_OK);
    CHECK_EQ_INT(memcmp(&d, &s.camera, sizeof d), 0);
    CHECK_EQ_INT(rt_anim_frame(&s, &a, 48, &d, &t0, &t1), RT_OK);
    CHECK_EQ_INT(memcmp(&d, &s.camera, sizeof d), 0);
    CHECK_EQ_INT(rt_anim_frame(&s, &a, 12, &d, &t0, &t1), RT_OK); /* 90 degrees, counter-clockwise from +y */
    CHECK_NEAR(d.lookfrom.x, 3, 1e-12);
    CHECK_NEAR(d.lookfrom.y, 2, 0);
    CHECK_NEAR(d.lookfrom.z, -13, 1e-12);
    CHECK_NEAR(d.vfov_deg, 20, 0);
    const rt_anim_opts none = {.turn_degrees = 360, .turn_frames = 0}; /* 0 frames: no turntable */
    CHECK_EQ_INT(rt_anim_frame(&s, &none, 12, &d, &t0, &t1), RT_OK);
    CHECK_EQ_INT(memcmp(&d, &s.camera, sizeof d), 0);
    const rt_anim_opts bad = {.turn_degrees = INFINITY, .turn_frames = 4};
    CHECK_EQ_INT(rt_anim_frame(&s, &bad, 1, &d, &t0, &t1), RT_EINVAL);
    rt_scene_free(&s);
}

/* The shutter: the book's [0, 1) after the frame's number where spheres
 * move, an instant otherwise, OPEN and CLOSE when given. */
static void test_shutter(void)
{
    rt_scene s;
    rt_scene_init(&s);
    s.camera.lookfrom = rt_v3(0, 0, 5);
    s.camera.lookat = rt_v3(0, 0, 0);
    rt_camera_desc d;
    double t0, t1;
    CHECK_EQ_INT(rt_anim_frame(&s, NULL, 7, &d, &t0, &t1), RT_OK); /* nothing moves: an instant */
    CHECK_NEAR(t0, 7, 0);
    CHECK_NEAR(t1, 7, 0);
    uint32_t m;
    rt_material lam = rt_scene_lambertian(rt_v3(0.5, 0.5, 0.5));
    CHECK_EQ_INT(rt_scene_add_material(&s, &lam, &m), RT_OK);
    CHECK_EQ_INT(rt_scene_add_mover(&s, rt_v3(0, 0, 0), rt_v3(1, 0, 0), 0.5, m, NULL), RT_OK);
    CHECK_EQ_INT(rt_anim_frame(&s, NULL, 0, &d, &t0, &t1), RT_OK); /* the book's [0, 1) */
    CHECK_NEAR(t0, 0, 0);
    CHECK_NEAR(t1, 1, 0);
    CHECK_EQ_INT(rt_anim_frame(&s, NULL, 3, &d, &t0, &t1), RT_OK);
    CHECK_NEAR(t0, 3, 0);
    CHECK_NEAR(t1, 4, 0);
    rt_anim_opts a = {0};
    CHECK_EQ_INT(rt_anim_parse_shutter("0.25,0.5", &a), RT_OK);
    CHECK_EQ_INT(rt_anim_frame(&s, &a, 3, &d, &t0, &t1), RT_OK);
    CHECK_NEAR(t0, 3.25, 0);
    CHECK_NEAR(t1, 3.5, 0);
    CHECK_EQ_INT(rt_anim_parse_shutter("0,0", &a), RT_OK);
    CHECK_EQ_INT(rt_anim_frame(&s, &a, 3, &d, &t0, &t1), RT_OK);
    CHECK_NEAR(t0, 3, 0);
    CHECK_NEAR(t1, 3, 0);
    const char *bad[] = {"0.5,0.25", "-0.1,0.5", "0,1.5", "0.5", "0,", ",1", "0,1x", "nan,1", "", "0;1"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        CHECK_EQ_INT(rt_anim_parse_shutter(bad[i], &a), RT_EINVAL);
    CHECK_NEAR(a.shutter_open, 0, 0); /* a refused value leaves the last one */
    a.shutter_open = 0.75; /* out of order when set directly */
    a.shutter_close = 0.5;
    CHECK_EQ_INT(rt_anim_frame(&s, &a, 3, &d, &t0, &t1), RT_EINVAL);
    CHECK_EQ_INT(rt_anim_parse_shutter("0.25,0.5", &a), RT_OK); /* frames 2..5 together */
    CHECK_EQ_INT(rt_anim_span(&s, &a, 2, 5, &t0, &t1), RT_OK);
    CHECK_NEAR(t0, 2.25, 0);
    CHECK_NEAR(t1, 5.5, 0);
    CHECK_EQ_INT(rt_anim_span(&s, NULL, 2, 5, &t0, &t1), RT_OK);
    CHECK_NEAR(t0, 2, 0);
    CHECK_NEAR(t1, 6, 0);
    CHECK_EQ_INT(rt_anim_span(&s, NULL, 5, 2, &t0, &t1), RT_EINVAL);
    rt_scene_free(&s);
}

/* The sums of a W x H render of s's frame `frame` with the shutter closed
 * at its start (every ray at time `frame`), the accelerator built for the
 * times [0, span_hi]; NULL when something failed. */
static int64_t *render_frame(const rt_scene *s, uint32_t frame, double span_hi)
{
    enum { W = 12, H = 8 };
    const rt_anim_opts a = {.shutter_set = 1};
    const rt_job j = {.width = W, .height = H, .samples = 4, .max_depth = 8, .seed = 3,
                      .diffuse = RT_DIFFUSE_LAMBERTIAN, .sampler = RT_SAMPLER_SOBOL, .roulette = 1};
    rt_camera_desc cam;
    double t0, t1;
    rt_accel *acc = NULL;
    rt_renderer r;
    int64_t *sums = calloc((size_t)W * H * 3, sizeof *sums);
    int ok = sums && !rt_anim_frame(s, &a, frame, &cam, &t0, &t1) &&
             !rt_accel_new_span(&acc, s, RT_ACCEL_BVH, 0.0, span_hi) && !rt_render_init(&r, s, acc, &j) &&
             !rt_render_frame(&r, &cam, t0, t1);
    if (ok)
        rt_render_rows(&r, 0, H, 0, j.samples, sums, 1);
    rt_accel_free(acc);
    if (!ok)
        free(sums);
    return ok ? sums : NULL;
}

/* A render of frame 3 sees the moving spheres where time 3 puts them: the
 * same sums as frame 0 of a scene whose spheres start there and stand
 * still; and the same whatever the span the accelerator was built for. */
static void test_render_frame(void)
{
    rt_scene moving, still;
    rt_scene_init(&moving);
    rt_scene_init(&still);
    rt_scene *sc[2] = {&moving, &still};
    for (int k = 0; k < 2; k++) {
        rt_scene *s = sc[k];
        s->camera.lookfrom = rt_v3(0, 1, 6);
        s->camera.lookat = rt_v3(1.5, 0, 0);
        s->camera.pixels = RT_PIXELS_BOOK2;
        uint32_t m;
        rt_material lam = rt_scene_lambertian(rt_v3(0.6, 0.4, 0.3));
        CHECK_EQ_INT(rt_scene_add_material(s, &lam, &m), RT_OK);
        for (int i = 0; i < 4; i++) {
            const rt_vec3 c0 = rt_v3(-1.0 + i * 0.5, 0.25 * i, 0), c1 = rt_v3(-0.5 + i * 0.5, 0.25 * i, -0.25);
            const rt_vec3 at3 = rt_v3_add(c0, rt_v3_scale(rt_v3_sub(c1, c0), 3.0)); /* rt_mover_center's */
            CHECK_EQ_INT(k ? rt_scene_add_mover(s, at3, at3, 0.4, m, NULL) : rt_scene_add_mover(s, c0, c1, 0.4, m, NULL),
                         RT_OK);
        }
    }
    int64_t *a = render_frame(&moving, 3, 4.0), *b = render_frame(&still, 0, 1.0),
            *c = render_frame(&moving, 3, 100.0), *z = render_frame(&moving, 0, 1.0);
    const size_t n = 12 * 8 * 3 * sizeof *a;
    CHECK_EQ_INT(a && b && c && z, 1);
    if (a && b && c && z) {
        CHECK_EQ_INT(memcmp(a, b, n), 0);
        CHECK_EQ_INT(memcmp(a, c, n), 0);
        CHECK_EQ_INT(memcmp(a, z, n) != 0, 1); /* frame 0 is another picture */
    }
    free(a);
    free(b);
    free(c);
    free(z);
    rt_scene_free(&moving);
    rt_scene_free(&still);
}

/* Keys travel in the broadcast bytes (version 3); a scene without keys
 * keeps its version. */
static void test_bytes(void)
{
    rt_scene s, back;
    rt_scene_init(&s);
    s.camera.lookfrom = rt_v3(0, 0, 5);
    s.camera.lookat = rt_v3(0, 0, 0);
    uint8_t *b;
    size_t n;
    CHECK_EQ_INT(rt_scene_serialize(&s, &b, &n), RT_OK);
    CHECK_EQ_INT(b[8], 1);
    free(b);
    const rt_camera_key k[2] = {key(0, rt_v3(0, 1, 5), 30), key(2.5, rt_v3(5, 1, 0), 50)};
    CHECK_EQ_INT(rt_anim_add_key(&s, &k[0]), RT_OK);
    CHECK_EQ_INT(rt_anim_add_key(&s, &k[1]), RT_OK);
    CHECK_EQ_INT(rt_scene_serialize(&s, &b, &n), RT_OK);
    CHECK_EQ_INT(b[8], 3);
    CHECK_EQ_INT(rt_scene_deserialize(&back, b, n), RT_OK);
    CHECK_EQ_INT(back.keys.n, 2);
    CHECK_EQ_INT(memcmp(back.keys.items, k, sizeof k), 0);
    rt_scene_free(&back);
    b[n - 12] = 3; /* the keys' count: the length no longer fits */
    CHECK_EQ_INT(rt_scene_deserialize(&back, b, n), RT_EFORMAT);
    free(b);
    rt_scene_free(&s);
}

/* Spheres moving along +x, at frame 3's times: where time 3.5 puts them,
 * found by the tree built for the times [0, 4] as by brute force. */
static void test_later_frame(void)
{
    rt_scene s;
    rt_scene_init(&s);
    uint32_t m;
    rt_material lam = rt_scene_lambertian(rt_v3(0.5, 0.5, 0.5));
    CHECK_EQ_INT(rt_scene_add_material(&s, &lam, &m), RT_OK);
    for (int i = 0; i < 32; i++)
        CHECK_EQ_INT(rt_scene_add_mover(&s, rt_v3(0, i, 0), rt_v3(1, i, 0), 0.25, m, NULL), RT_OK);
    rt_world *tree, *brute;
    CHECK_EQ_INT(rt_world_build(&tree, &s, RT_WORLD_BVH, 0.0, 4.0), RT_OK);
    CHECK_EQ_INT(rt_world_build(&brute, &s, RT_WORLD_BRUTE, 0.0, 4.0), RT_OK);
    int found = 0, agree = 0;
    for (int i = 0; i < 32; i++) {
        const rt_ray r = {.orig = rt_v3(3.5, i, -5), .dir = rt_v3(0, 0, 1)};
        rt_whit ht, hb;
        const int a = rt_world_closest(tree, &r, 3.5, 0.001, INFINITY, &ht);
        const int b = rt_world_closest(brute, &r, 3.5, 0.001, INFINITY, &hb);
        found += a;
        agree += a == b && (!a || (ht.index == hb.index && ht.t == hb.t));
    }
    CHECK_EQ_INT(found, 32);
    CHECK_EQ_INT(agree, 32);
    rt_world_free(tree);
    rt_world_free(brute);
    rt_scene_free(&s);
}

int main(void)
{
    test_keys();
    test_turntable();
    test_shutter();
    test_bytes();
    test_later_frame();
    test_render_frame();
    CHECK_DONE();
}
