/* path2_start.h - a book-2 path's start (the camera ray of a pixel's
 * sample, its sampler and its time) and the background's light where it
 * leaves the scene: path2.c's loop and path_lanes.c's start and end their
 * paths alike. Core-internal. */
#ifndef RT_PATH2_START_H
#define RT_PATH2_START_H

#include "path.h"

/* A new path for sample `sample` of pc's pixel: its camera ray, its
 * sampler and its time. */
static inline void rt_path2_start(const rt_renderer *r, const pixel_ctx *pc, uint32_t sample, path *p, double *time)
{
    const uint32_t W = r->job.width, H = r->job.height;
    p->smp = rt_sampler_start(&pc->smp, sample);
    p->thr = rt_v3(1, 1, 1);
    p->col = rt_v3(0, 0, 0);
    p->aov = (aov_rec){0, {0, 0, 0}, {0, 0, 0}};
    double du, dv, u, v;
    rt_sampler_pixel2d(&p->smp, &du, &dv);
    if (r->scene->camera.pixels == RT_PIXELS_BOOK2) { /* pixel centres, jitter in [-0.5, 0.5) */
        u = ((double)pc->x + du) / (double)W;
        v = 1.0 - ((double)pc->y + dv) / (double)H;
    } else {
        u = ((double)pc->x + du) / (double)(W > 1 ? W - 1 : 1);
        v = ((double)(H - 1 - pc->y) + dv) / (double)(H > 1 ? H - 1 : 1);
    }
    rt_vec3 d = {0, 0, 0};
    if (r->camera.lens_radius > 0.0)
        d = rt_sampler_lens(&p->smp);
    p->ray = rt_camera_ray_lens(&r->camera, u, v, d.x, d.y);
    rt_sampler_seek(&p->smp, RT_SAMPLER2_DIM_TIME);
    *time = r->time0 + rt_sampler_get1d(&p->smp) * (r->time1 - r->time0); /* [0, 1): u itself */
}

/* The background's light along direction dir: s's colour, or book 1's sky
 * gradient by the direction's height. */
static inline rt_vec3 rt_path2_background(const rt_scene *s, rt_vec3 dir)
{
    if (s->background_kind != RT_BACKGROUND_SKY)
        return s->background;
    const double t = 0.5 * (rt_v3_unit(dir).y + 1.0);
    return rt_v3_add(rt_v3_scale(s->sky_bottom, 1.0 - t), rt_v3_scale(s->sky_top, t));
}

#endif
