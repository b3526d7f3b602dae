/* camera.c - the book's thin-lens camera (lookfrom/lookat/vup, vfov,
 * aperture, focus distance). */
#include "camera.h"
#include "core_internal.h"

#include <math.h>

#include "sample.h"
#include "status.h"

int rt_camera_init(rt_camera *cam, const rt_camera_desc *d, double aspect)
{
    if (!(d->vfov_deg > 0.0 && d->vfov_deg < 180.0) || !(aspect > 0.0) || !isfinite(aspect) ||
        !(d->focus_dist > 0.0) || !(d->aperture >= 0.0))
        return RT_EINVAL;
    rt_vec3 back = rt_v3_sub(d->lookfrom, d->lookat);
    if (rt_v3_len2(back) == 0.0)
        return RT_EINVAL;
    const double pi = 3.14159265358979323846;
    double h = tan(d->vfov_deg * pi / 180.0 / 2.0);
    double vh = 2.0 * h, vw = aspect * vh;
    cam->w = rt_v3_unit(back);
    rt_vec3 side = rt_v3_cross(d->vup, cam->w);
    if (!(rt_v3_len2(side) > 1e-24))
        return RT_EINVAL;
    cam->u = rt_v3_unit(side);
    cam->v = rt_v3_cross(cam->w, cam->u);
    cam->origin = d->lookfrom;
    cam->horizontal = rt_v3_scale(cam->u, d->focus_dist * vw);
    cam->vertical = rt_v3_scale(cam->v, d->focus_dist * vh);
    cam->lower_left = rt_v3_sub(rt_v3_sub(rt_v3_sub(cam->origin, rt_v3_scale(cam->horizontal, 0.5)),
                                          rt_v3_scale(cam->vertical, 0.5)),
                                rt_v3_scale(cam->w, d->focus_dist));
    cam->lens_radius = d->aperture / 2.0;
    return RT_OK;
}

int rt_camera_orbit(rt_camera_desc *d, uint32_t frame, double degrees, uint32_t frames)
{
    const double len = rt_v3_len(d->vup);
    if (!frames || !isfinite(degrees) || !(len > 0))
        return RT_EINVAL;
    double turns = (double)frame * degrees / (360.0 * (double)frames);
    turns -= floor(turns); /* [0, 1]: exact */
    const uint32_t q = (uint32_t)(uint64_t)(turns * 4294967296.0);
    if (q == 0)
        return RT_OK; /* whole turns: the scene's own camera, to the bit */
    double c, s;
    rt_sample_cos_sin_turn(q, &c, &s);
    const rt_vec3 k = rt_v3_scale(d->vup, 1.0 / len), v = rt_v3_sub(d->lookfrom, d->lookat);
    const rt_vec3 turned = rt_v3_add(rt_v3_add(rt_v3_scale(v, c), rt_v3_scale(rt_v3_cross(k, v), s)),
                                     rt_v3_scale(k, rt_v3_dot(k, v) * (1.0 - c)));
    d->lookfrom = rt_v3_add(d->lookat, turned);
    return RT_OK;
}

rt_ray rt_camera_ray_lens(const rt_camera *cam, double s, double t, double lx, double ly)
{
    rt_vec3 offset = rt_v3(0, 0, 0);
    if (cam->lens_radius > 0.0) {
        rt_vec3 rd = rt_v3_scale(rt_v3(lx, ly, 0.0), cam->lens_radius);
        offset = rt_v3_add(rt_v3_scale(cam->u, rd.x), rt_v3_scale(cam->v, rd.y));
    }
    rt_ray ray;
    ray.orig = rt_v3_add(cam->origin, offset);
    rt_vec3 target = rt_v3_add(rt_v3_add(cam->lower_left, rt_v3_scale(cam->horizontal, s)),
                               rt_v3_scale(cam->vertical, t));
    ray.dir = rt_v3_sub(rt_v3_sub(target, cam->origin), offset);
    return ray;
}

rt_ray rt_camera_ray(const rt_camera *cam, double s, double t, rt_rng *r)
{
    if (cam->lens_radius > 0.0) {
        rt_vec3 d = rt_sample_in_unit_disk(r);
        return rt_camera_ray_lens(cam, s, t, d.x, d.y);
    }
    return rt_camera_ray_lens(cam, s, t, 0.0, 0.0);
}
