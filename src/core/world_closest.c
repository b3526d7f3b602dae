/* world_closest.c - the closest quad, moving or static sphere along a ray: brute
 * force (the oracle), or the wide tree of world.c's build with the box test
 * of the instruction set (world_traverse.h, once per set as bvh.c does). */
#include "world_internal.h"

#include "bvh.h"
#include "fbox.h"

#if RT_BVH_HAVE_SSE2
#include <immintrin.h>
#endif

#define WSTACK ((WWIDTH - 1) * RT_WORLD_DEPTH_MAX)

#define WTRAVERSE closest_base
#define WTRAV_AVX 0
#include "world_traverse.h"
#undef WTRAVERSE
#undef WTRAV_AVX

#if RT_BVH_HAVE_AVX
#ifdef __clang__
#pragma clang attribute push(__attribute__((target("avx"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx")
#endif
#define WTRAVERSE closest_avx
#define WTRAV_AVX 1
#include "world_traverse.h"
#undef WTRAVERSE
#undef WTRAV_AVX
static int walk_avx(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax, rt_whit *hit)
{
    double best_t = tmax;
    uint32_t best = UINT32_MAX;
    closest_avx(w, ray, time, tmin, &best_t, &best, 1, 0);
    return rt_world_hit_of(w, best_t, best, hit);
}
static int any_avx(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax, uint32_t item)
{
    double best_t = tmax;
    uint32_t best = item;
    return closest_avx(w, ray, time, tmin, &best_t, &best, 1, 1);
}
#ifdef __clang__
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif

/* The other modes' walks (the SSE2 or portable box test, brute force). */
static __attribute__((noinline)) int walk_base(const rt_world *w, const rt_ray *ray, double time, double tmin,
                                               double *best_t, uint32_t *best, int simd, int anyhit)
{
    return anyhit ? closest_base(w, ray, time, tmin, best_t, best, simd, 1)
                  : closest_base(w, ray, time, tmin, best_t, best, simd, 0);
}

static __attribute__((noinline)) int walk_brute(const rt_world *w, const rt_ray *ray, double time, double tmin,
                                                double *best_t, uint32_t *best, int anyhit)
{
    const uint32_t self = anyhit ? *best : UINT32_MAX; /* skipped as in world_traverse.h */
    for (uint32_t i = 0; i < w->nitems; i++)
        if (i != self && rt_world_test_item(w, i, ray, time, tmin, best_t, best) && anyhit)
            return 1;
    return 0;
}

/* The hit (*best_t, *best) replaced by any nearer item, or as near and
 * before it, by the mode's walk; with anyhit, returns 1 at the first. */
static int query(const rt_world *w, const rt_ray *ray, double time, double tmin, double *best_t, uint32_t *best,
                 int anyhit)
{
    switch (w->n_nodes ? w->mode : RT_WORLD_BRUTE) {
    case RT_WORLD_BVH:
    case RT_WORLD_BVH_SSE:
        return walk_base(w, ray, time, tmin, best_t, best, RT_BVH_HAVE_SSE2, anyhit);
    case RT_WORLD_BVH_SCALAR:
        return walk_base(w, ray, time, tmin, best_t, best, 0, anyhit);
    default:
        return walk_brute(w, ray, time, tmin, best_t, best, anyhit);
    }
}

static int walk_other(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax, rt_whit *hit)
{
    double best_t = tmax;
    uint32_t best = UINT32_MAX;
    query(w, ray, time, tmin, &best_t, &best, 0);
    return rt_world_hit_of(w, best_t, best, hit);
}

static int any_other(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax, uint32_t item)
{
    double best_t = tmax;
    uint32_t best = item;
    return query(w, ray, time, tmin, &best_t, &best, 1);
}

void rt_world_pick(rt_world *w)
{
    w->closest = walk_other;
    w->occluded = any_other;
#if RT_BVH_HAVE_AVX
    if (w->n_nodes && w->mode == RT_WORLD_BVH) {
        w->closest = walk_avx;
        w->occluded = any_avx;
    }
    if (w->flat && w->mode == RT_WORLD_BVH)
        rt_world_flat_pick(w);
#endif
}

int rt_world_closest(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax, rt_whit *hit)
{
    return w->closest(w, ray, time, tmin, tmax, hit);
}

int rt_world_occluded(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax, uint32_t kind,
                      uint32_t index)
{
    return w->occluded(w, ray, time, tmin, tmax, rt_world_item(w, kind, index));
}

int rt_world_shape_t(const rt_world *w, uint32_t kind, uint32_t index, const rt_ray *ray, double time, double tmin,
                     double *t)
{
    if (kind == RT_SHAPE_QUAD)
        return rt_quad_t(&w->quads[index], ray, tmin, INFINITY, t);
    const double a = rt_v3_len2(ray->dir);
    if (kind == RT_SHAPE_MOVER) {
        const rt_mover *m = &w->s->shapes.movers.items[index];
        return rt_sphere_root(rt_mover_center(m, time), m->radius * m->radius, ray, a, tmin, t);
    }
    const rt_sphere *sp = &w->s->spheres[index];
    return rt_sphere_root(sp->center, sp->radius * sp->radius, ray, a, tmin, t);
}
