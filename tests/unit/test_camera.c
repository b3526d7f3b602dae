/* test_camera.c - camera rays: centre ray looks at lookat, corners span the
 * field of view, the lens keeps rays converging on the focus plane. */
#include <string.h>

#include "anim.h"
#include "camera.h"
#include "check.h"
#include "status.h"

int main(void)
{
    rt_camera_desc d = {.lookfrom = rt_v3(13, 2, 3),
                        .lookat = rt_v3(0, 0, 0),
                        .vup = rt_v3(0, 1, 0),
                        .vfov_deg = 20.0,
                        .focus_dist = 10.0};
    rt_camera cam;
    CHECK_EQ_INT(rt_camera_init(&cam, &d, 1.5), RT_OK);
    rt_rng rng = rt_rng_for_stream(3, RT_STREAM_TEST);
    rt_ray c = rt_camera_ray(&cam, 0.5, 0.5, &rng);
    rt_vec3 want = rt_v3_unit(rt_v3_sub(d.lookat, d.lookfrom));
    rt_vec3 got = rt_v3_unit(c.dir);
    CHECK_NEAR(got.x, want.x, 1e-12);
    CHECK_NEAR(got.y, want.y, 1e-12);
    CHECK_NEAR(got.z, want.z, 1e-12);
    /* Vertical field of view: top and bottom centre rays are 20 deg apart. */
    rt_vec3 top = rt_v3_unit(rt_camera_ray(&cam, 0.5, 1.0, &rng).dir);
    rt_vec3 bot = rt_v3_unit(rt_camera_ray(&cam, 0.5, 0.0, &rng).dir);
    CHECK_NEAR(acos(rt_v3_dot(top, bot)) * 180.0 / 3.14159265358979323846, 20.0, 1e-9);
    /* Aspect: horizontal extent is 1.5 x the vertical one. */
    CHECK_NEAR(rt_v3_len(cam.horizontal) / rt_v3_len(cam.vertical), 1.5, 1e-12);
    /* Thin lens: rays from different lens points meet on the focus plane. */
    d.aperture = 2.0;
    CHECK_EQ_INT(rt_camera_init(&cam, &d, 1.5), RT_OK);
    int meet = 1;
    for (int i = 0; i < 100; i++) {
        rt_ray r = rt_camera_ray(&cam, 0.3, 0.7, &rng);
        rt_vec3 p = rt_v3_add(r.orig, r.dir); /* dir spans origin -> focus plane */
        rt_vec3 q = rt_v3_add(rt_v3_add(cam.lower_left, rt_v3_scale(cam.horizontal, 0.3)),
                              rt_v3_scale(cam.vertical, 0.7));
        meet &= rt_v3_len(rt_v3_sub(p, q)) < 1e-9;
        meet &= rt_v3_len(rt_v3_sub(r.orig, d.lookfrom)) <= 1.0 + 1e-12;
    }
    CHECK(meet);
    /* Degenerate frames are refused. */
    rt_camera_desc bad = d;
    bad.lookat = bad.lookfrom;
    CHECK_EQ_INT(rt_camera_init(&cam, &bad, 1.5), RT_EINVAL);
    bad = d;
    bad.vup = rt_v3(-13, -2, -3);
    CHECK_EQ_INT(rt_camera_init(&cam, &bad, 1.5), RT_EINVAL);
    bad = d;
    bad.vfov_deg = 180;
    CHECK_EQ_INT(rt_camera_init(&cam, &bad, 1.5), RT_EINVAL);
    /* The turntable: 90 degrees about +y takes (13, 2, 3) to (3, 2, -13);
     * the distance to lookat and the height along vup are kept; a whole
     * turn gives the start back to the bit; frame 0 is the scene's camera. */
    rt_camera_desc o = d;
    o.lookat = rt_v3(1, 0, -1);
    o.lookfrom = rt_v3(14, 2, 2);
    o.vup = rt_v3(0, 2, 0); /* not unit */
    CHECK_EQ_INT(rt_camera_orbit(&o, 1, 90.0, 1), RT_OK);
    CHECK_NEAR(o.lookfrom.x, 4.0, 1e-12);
    CHECK_NEAR(o.lookfrom.y, 2.0, 1e-12);
    CHECK_NEAR(o.lookfrom.z, -14.0, 1e-12);
    for (uint32_t f = 0; f < 48; f += 11) {
        rt_camera_desc t = d;
        CHECK_EQ_INT(rt_camera_orbit(&t, f, 360.0, 48), RT_OK);
        rt_vec3 v = rt_v3_sub(t.lookfrom, t.lookat);
        CHECK_NEAR(rt_v3_len(v), rt_v3_len(rt_v3_sub(d.lookfrom, d.lookat)), 1e-12);
        CHECK_NEAR(v.y, 2.0, 1e-12);
        double want_angle = f * 360.0 / 48 * 3.14159265358979323846 / 180;
        CHECK_NEAR(remainder(atan2(-v.z, v.x) - atan2(-3.0, 13.0) - want_angle, 2 * 3.14159265358979323846), 0.0, 1e-8);
    }
    rt_camera_desc w = d;
    w.lookat = rt_v3(0.1, 0.7, -0.3);
    d.lookat = w.lookat;
    CHECK_EQ_INT(rt_camera_orbit(&w, 48, 360.0, 48), RT_OK);
    CHECK(memcmp(&w.lookfrom, &d.lookfrom, sizeof w.lookfrom) == 0);
    w = d;
    CHECK_EQ_INT(rt_camera_orbit(&w, 0, 30.0, 7), RT_OK);
    CHECK(memcmp(&w.lookfrom, &d.lookfrom, sizeof w.lookfrom) == 0);
    CHECK_EQ_INT(rt_camera_orbit(&w, 1, 30.0, 0), RT_EINVAL);
    CHECK_EQ_INT(rt_camera_orbit(&w, 1, NAN, 1), RT_EINVAL);
    w.vup = rt_v3(0, 0, 0);
    CHECK_EQ_INT(rt_camera_orbit(&w, 1, 30.0, 1), RT_EINVAL);

    /* A frame's camera and time (anim.h): frame 0 without a turntable is
     * the scene's camera; with one, the orbit of the frame's number; the
     * time interval is the frame's (a scene without moving spheres: no
     * shutter, every ray at the frame's time; test_anim checks the rest). */
    rt_scene sc;
    rt_scene_init(&sc);
    sc.camera = d;
    rt_camera_desc fc;
    double t0 = -1, t1 = -1;
    CHECK_EQ_INT(rt_anim_frame(&sc, NULL, 0, &fc, &t0, &t1), RT_OK);
    CHECK(memcmp(&fc, &d, sizeof fc) == 0);
    CHECK(t0 == 0.0 && t1 == 0.0);
    const rt_anim_opts turn = {.turn_degrees = 360.0, .turn_frames = 48};
    rt_camera_desc orbited = d;
    CHECK_EQ_INT(rt_camera_orbit(&orbited, 7, 360.0, 48), RT_OK);
    CHECK_EQ_INT(rt_anim_frame(&sc, &turn, 7, &fc, &t0, &t1), RT_OK);
    CHECK(memcmp(&fc.lookfrom, &orbited.lookfrom, sizeof fc.lookfrom) == 0);
    CHECK(memcmp(&fc.lookfrom, &d.lookfrom, sizeof fc.lookfrom) != 0);
    CHECK_NEAR(t0, 7.0, 0.0);
    CHECK_NEAR(t1, 7.0, 0.0);
    const rt_anim_opts nan_turn = {.turn_degrees = NAN, .turn_frames = 4};
    CHECK_EQ_INT(rt_anim_frame(&sc, &nan_turn, 1, &fc, &t0, &t1), RT_EINVAL);
    rt_scene_free(&sc);
    CHECK_DONE();
}
