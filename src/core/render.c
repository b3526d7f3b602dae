/* render.c - the render core's entry points: a renderer for a job, one
 * sample or one pixel's pilot (path.h), and a block of rows with OpenMP
 * over its pixels (the path loop: dispatch.c; a stream of units: team.c). */
#include "render.h"
#include "core_internal.h"

#include <math.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "dispatch.h"
#include "lights.h"
#include "path.h"
#include "path2.h"
#include "path_lanes.h"
#include "status.h"

int rt_render_init(rt_renderer *r, const rt_scene *s, const rt_accel *a, const rt_job *job)
{
    if (job->width == 0 || job->height == 0 || job->samples == 0 || job->max_depth == 0)
        return RT_EINVAL;
    r->scene = s;
    r->accel = a;
    r->job = *job;
    if (!r->job.roulette_depth)
        r->job.roulette_depth = RT_RENDER_ROULETTE_DEPTH;
    r->stop = NULL;
    r->bvh_avx = RT_BVH_HAVE_AVX ? rt_accel_bvh_avx(a) : NULL;
    r->primary = NULL;
    r->wlists = NULL;
    r->lay = rt_job_layout(job);
    r->world = rt_accel_world(a);
    r->lights = job->light != RT_LIGHT_BRUTE && job->diffuse == RT_DIFFUSE_LAMBERTIAN ? rt_accel_lights(a) : NULL;
    r->light_targets = rt_lights_target_count(r->lights);
    r->no_look_ahead = 0;
    r->no_caustic = 0;
    r->lanes = rt_path_lanes_for(r);
    return rt_render_frame(r, &s->camera, 0.0, 1.0);
}

int rt_render_frame(rt_renderer *r, const rt_camera_desc *cam, double t0, double t1)
{
    if (!(t0 <= t1) || !isfinite(t0) || !isfinite(t1))
        return RT_EINVAL;
    r->time0 = t0;
    r->time1 = t1;
    return rt_camera_init(&r->camera, cam, (double)r->job.width / (double)r->job.height);
}

rt_vec3 rt_render_sample(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t sample, uint64_t *segments)
{
    if (r->world)
        return rt_path2_sample(r, x, y, sample, segments);
    const pixel_ctx pc = pixel_start(r, x, y, pixel_key(r, x, y), 0);
    path p;
    path_start(&pc, sample, &p);
    path_trace(&pc, &p, 0, segments, NULL, 0);
    return p.col;
}

uint32_t rt_render_sample_rays(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t sample, rt_ray *rays)
{
    uint64_t segs = 0;
    const pixel_ctx pc = pixel_start(r, x, y, pixel_key(r, x, y), 0);
    path p;
    path_start(&pc, sample, &p);
    path_trace(&pc, &p, 0, &segs, rays, 0);
    return (uint32_t)segs;
}

uint32_t rt_render_pilot(const rt_renderer *r, uint32_t x, uint32_t y, uint64_t *segments)
{
    if (r->world)
        return rt_path2_pilot(r, x, y, segments);
    const pixel_ctx pc = pixel_start(r, x, y, pixel_key(r, x, y), 0);
    return pilot_count(&pc, segments);
}

uint64_t rt_render_rows(const rt_renderer *r, uint32_t y0, uint32_t y1, uint32_t s0, uint32_t s1, int64_t *acc,
                        int nthreads)
{
    const uint32_t W = r->job.width;
    const long npix = (long)(y1 - y0) * W;
    uint64_t total = 0;
    rt_dispatch_fn fn = rt_dispatch_pick(r);
#ifdef _OPENMP
    if (nthreads <= 0)
        nthreads = omp_get_max_threads();
#else
    (void)nthreads;
#endif
    /* guided: each thread starts on a long run of neighbouring pixels and
     * the runs shrink (to 4 pixels) towards the end of the block. */
#pragma omp parallel for schedule(guided, 4) reduction(+ : total) num_threads(nthreads) if (nthreads > 1)
    for (long i = 0; i < npix; i++)
        if (!rt_dispatch_stopped(r))
            total += rt_dispatch_block_pixel(r, fn, 0, W, y0, s0, s1, i, acc);
    return total;
}
