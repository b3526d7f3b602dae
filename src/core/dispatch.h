/* dispatch.h - the path loop for a job and a CPU (dispatch.c), and the
 * pixels of a block as render.c's rows and team.c's units lay them out.
 * Core-internal: included by render.c and team.c only. */
#ifndef RT_DISPATCH_H
#define RT_DISPATCH_H

#include <stdint.h>

#include "path_lanes.h"
#include "render.h"

/* Adds samples [s0, s1) of pixel (x, y) to its values px (r->lay) and
 * returns the ray segments traced. */
typedef uint64_t (*rt_dispatch_fn)(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t s0, uint32_t s1,
                                   int64_t *px);

/* The path loop for r's job and CPU. */
rt_dispatch_fn rt_dispatch_pick(const rt_renderer *r);

/* Whether r was told to stop (rt_renderer.stop). */
static inline int rt_dispatch_stopped(const rt_renderer *r)
{
    return r->stop && *r->stop;
}

/* Pixel i of a block of columns [x0, x0 + w) and rows from y0, row by
 * row: its samples [s0, s1) added to acc[ch i ..]; returns the ray
 * segments traced. */
static inline uint64_t rt_dispatch_block_pixel(const rt_renderer *r, rt_dispatch_fn fn, uint32_t x0, uint32_t w,
                                               uint32_t y0, uint32_t s0, uint32_t s1, long i, int64_t *acc)
{
    uint32_t x = x0 + (uint32_t)(i % w), y = y0 + (uint32_t)(i / w);
    return fn(r, x, y, s0, s1, acc + i * r->lay.ch);
}

/* The run of pixels of such a block that starts at pixel i and ends by
 * b: in the lanes (r->lanes) as many pixels as keep them busy
 * (rt_path_lanes_run_pixels), else pixel i alone; *next: the pixel after
 * it. Returns the ray segments traced. */
static inline uint64_t rt_dispatch_block_run(const rt_renderer *r, rt_dispatch_fn fn, uint32_t x0, uint32_t w,
                                             uint32_t y0, uint32_t s0, uint32_t s1, long i, long b, int64_t *acc,
                                             long *next)
{
    if (!r->lanes) {
        *next = i + 1;
        return rt_dispatch_block_pixel(r, fn, x0, w, y0, s0, s1, i, acc);
    }
    const long n = (long)rt_path_lanes_run_pixels(s1 - s0);
    *next = b - i < n ? b : i + n;
    return rt_path_lanes_run(r, x0, w, y0, s0, s1, i, *next, acc);
}

#endif
