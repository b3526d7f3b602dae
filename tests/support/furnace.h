/* furnace.h - the furnace scene of the bias tests (test_furnace.c,
 * test_adaptive.c): a lambertian sphere of albedo 0.1, 0.06, 0.02 filling
 * the view through a lens, under a uniform white sky. Every camera ray hits
 * it and every scattered ray leaves it for the sky, so each pixel is the
 * albedo in expectation; the roulette's survival there is 0.8. */
#ifndef RT_TEST_FURNACE_H
#define RT_TEST_FURNACE_H

#include "accel.h"
#include "check.h"
#include "scene.h"
#include "status.h"

static inline rt_vec3 furnace_albedo(void) { return rt_v3(0.1, 0.06, 0.02); }

/* Fills *s and *a (free both after). */
static inline void furnace_scene(rt_scene *s, rt_accel **a)
{
    rt_scene_init(s);
    CHECK_EQ_INT(rt_scene_add(s, rt_v3(0, 0, -3), 1.0, rt_scene_lambertian(furnace_albedo())), RT_OK);
    s->sky_bottom = s->sky_top = rt_v3(1, 1, 1);
    s->camera = (rt_camera_desc){.lookfrom = rt_v3(0, 0, 0),
                                 .lookat = rt_v3(0, 0, -1),
                                 .vup = rt_v3(0, 1, 0),
                                 .vfov_deg = 20.0,
                                 .aperture = 0.5,
                                 .focus_dist = 3.0};
    CHECK_EQ_INT(rt_accel_new(a, s, RT_ACCEL_BVH), RT_OK);
}

#endif
