/* dispatch.c - the path loop (path.h's pixel), four times: in the baseline
 * instruction set, and compiled for AVX with the BVH's AVX traversal
 * inlined (no fused multiply-add in either: every operation rounds the
 * same, so the pixels are the same bits; the determinism test compares the
 * two). flatten inlines the whole path loop into each, the intersector
 * included: 5.7 % faster renders than calling the AVX traversal out of line
 * (scripts/ab_render.sh, 1.057 twice). Each twice again: for plain jobs,
 * and for jobs with adaptive sampling or buffers (pixel's extras). */
#include "dispatch.h"

#include "path.h"
#include "path2.h"

__attribute__((flatten)) static uint64_t pixel_base(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t s0,
                                                    uint32_t s1, int64_t *px)
{
    return pixel(r, x, y, s0, s1, px, 0, 0);
}

__attribute__((flatten)) static uint64_t pixel_base_x(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t s0,
                                                      uint32_t s1, int64_t *px)
{
    return pixel(r, x, y, s0, s1, px, 0, 1);
}

#if RT_BVH_HAVE_AVX
__attribute__((target("avx"), flatten)) static uint64_t pixel_avx(const rt_renderer *r, uint32_t x, uint32_t y,
                                                                   uint32_t s0, uint32_t s1, int64_t *px)
{
    return pixel(r, x, y, s0, s1, px, 1, 0);
}

__attribute__((target("avx"), flatten)) static uint64_t pixel_avx_x(const rt_renderer *r, uint32_t x, uint32_t y,
                                                                     uint32_t s0, uint32_t s1, int64_t *px)
{
    return pixel(r, x, y, s0, s1, px, 1, 1);
}
#endif

rt_dispatch_fn rt_dispatch_pick(const rt_renderer *r)
{
    const int extras = r->lay.ch > 3;
    if (r->world)
        return rt_path2_pixel;
#if RT_BVH_HAVE_AVX
    if (r->bvh_avx)
        return extras ? pixel_avx_x : pixel_avx;
#endif
    return extras ? pixel_base_x : pixel_base;
}
