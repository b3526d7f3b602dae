/* test_camera.c - camera rays: centre ray looks at lookat, corners span the
 * field of view, the lens keeps rays converging on the focus plane. */
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
    CHECK_DONE();
}
