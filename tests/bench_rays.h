/* bench_rays.h - the rays a benchmark times: every segment of every path
 * the renderer traces for its whole image, in render order. */
#ifndef RT_TEST_BENCH_RAYS_H
#define RT_TEST_BENCH_RAYS_H

#include <stdlib.h>

#include "array.h"
#include "render.h"
#include "status.h"

/* Two exact intersectors' answers differ: a hit against a miss, another t
 * or another sphere (rt_sphere_closer's rule settles exact ties). */
static inline int bench_hits_differ(int ha, const rt_hit *a, int hb, const rt_hit *b)
{
    return ha != hb || (ha && (a->t != b->t || a->prim != b->prim));
}

/* *rays is malloc'd; RT_OK, or RT_ENOMEM (and nothing allocated). */
static int bench_capture_rays(const rt_renderer *r, rt_ray **rays, size_t *n)
{
    size_t cap = 0;
    *rays = NULL;
    *n = 0;
    for (uint32_t y = 0; y < r->p.height; y++)
        for (uint32_t x = 0; x < r->p.width; x++)
            for (uint32_t k = 0; k < r->p.samples; k++) {
                if (rt_array_reserve((void **)rays, &cap, *n + r->p.max_depth, sizeof **rays)) {
                    free(*rays);
                    *rays = NULL;
                    return RT_ENOMEM;
                }
                *n += rt_render_sample_rays(r, x, y, k, *rays + *n);
            }
    return RT_OK;
}

#endif
