/* path2.h - the book-2 path loop (path2.c): what dispatch.c and render.c
 * call for scenes with book-2 content (rt_renderer.world set).
 * Core-internal. */
#ifndef RT_PATH2_H
#define RT_PATH2_H

#include <stdint.h>

#include "render.h"

/* dispatch.h's rt_dispatch_fn for book-2 scenes. */
uint64_t rt_path2_pixel(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t s0, uint32_t s1, int64_t *px);
/* One sample's colour, and a pixel's pilot count (render.c's entry points). */
rt_vec3 rt_path2_sample(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t sample, uint64_t *segments);
uint32_t rt_path2_pilot(const rt_renderer *r, uint32_t x, uint32_t y, uint64_t *segments);

#endif
