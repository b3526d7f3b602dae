/* bench_rays.h - the rays a benchmark times: every segment of every path
 * the renderer traces for its whole image, in render order. */
#ifndef RT_TEST_BENCH_RAYS_H
#define RT_TEST_BENCH_RAYS_H

#include <stdlib.h>

#include "core_internal.h"
#include "array.h"
#include "render.h"
#include "status.h"

/* Two exact intersectors' answers differ: a hit against a miss, another t
 * or another sphere (rt_sphere_closer's rule settles exact ties). */
static inline int bench_hits_differ(int ha, const rt_hit *a, int hb, const rt_hit *b)
{
    return ha != hb || (ha && (a->t != b->t || a->prim != b->prim));
}

/* *rays is malloc'd, the paths one after the other (pixel by pixel, sample
 * by sample); with lens not NULL, *lens is malloc'd too and holds each
 * path's number of rays. RT_OK, or RT_ENOMEM (and nothing allocated). */
static int bench_capture_rays(const rt_renderer *r, rt_ray **rays, size_t *n, uint32_t **lens)
{
    size_t cap = 0, paths = (size_t)r->job.width * r->job.height * r->job.samples, path = 0;
    *rays = NULL;
    *n = 0;
    if (lens && !(*lens = malloc(paths * sizeof **lens)))
        return RT_ENOMEM;
    for (uint32_t y = 0; y < r->job.height; y++)
        for (uint32_t x = 0; x < r->job.width; x++)
            for (uint32_t k = 0; k < r->job.samples; k++, path++) {
                if (rt_array_reserve((void **)rays, &cap, *n + r->job.max_depth, sizeof **rays)) {
                    free(*rays);
                    *rays = NULL;
                    if (lens) {
                        free(*lens);
                        *lens = NULL;
                    }
                    return RT_ENOMEM;
                }
                uint32_t len = rt_render_sample_rays(r, x, y, k, *rays + *n);
                if (lens)
                    (*lens)[path] = len;
                *n += len;
            }
    return RT_OK;
}

#endif
