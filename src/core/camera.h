/* camera.h - thin-lens camera: turns image-plane coordinates into rays. */
#ifndef RT_CAMERA_H
#define RT_CAMERA_H

#include "rng.h"
#include "scene.h"
#include "vec.h"

typedef struct rt_camera {
    rt_vec3 origin, lower_left, horizontal, vertical;
    rt_vec3 u, v, w;
    double lens_radius;
} rt_camera;

/* aspect = image width / height. Fails with RT_EINVAL for a degenerate frame
 * (lookfrom == lookat, vup parallel to the view direction, bad fov). */
int rt_camera_init(rt_camera *cam, const rt_camera_desc *d, double aspect);

/* The turntable (issue 37, being built): lookfrom turned about the axis
 * through lookat along vup by frame x degrees / frames (counter-clockwise
 * seen from vup's side), so a frame's camera depends on its number alone.
 * The angle goes through a 32-bit fraction of a turn and the table of
 * rt_sample_cos_sin_turn: the same bits on every node, no libm. RT_EINVAL
 * for frames 0, a non-finite angle or a zero vup. */
int rt_camera_orbit(rt_camera_desc *d, uint32_t frame, double degrees, uint32_t frames);

/* Ray through (s, t) of the viewport, s to the right and t upward, both in
 * [0, 1]; draws the lens sample from r (only when the lens has a radius). */
rt_ray rt_camera_ray(const rt_camera *cam, double s, double t, rt_rng *r);

#endif
