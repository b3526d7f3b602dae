/* accel.c - the intersector front end: dispatch to our BVH (AVX, SSE2 or
 * portable box test), brute force (every sphere for every ray, as the seed
 * renderers do) or Embree. */
#include "accel.h"

#include <stdlib.h>
#include <string.h>

#include "bvh.h"
#include "lights.h"
#include "sphere.h"
#include "status.h"
#include "world.h"

#ifdef RT_HAVE_EMBREE
#include "accel_embree.h"
#endif

struct rt_accel {
    rt_accel_kind kind;
    const rt_scene *scene;
    rt_bvh *bvh;
    void *embree;
    rt_world *world;
    rt_lights *lights;
};

/* The world's traversal for the spheres' one: the same box test. */
static rt_world_mode world_mode(rt_accel_kind kind)
{
    switch (kind) {
    case RT_ACCEL_BRUTE:
        return RT_WORLD_BRUTE;
    case RT_ACCEL_BVH_SSE:
        return RT_WORLD_BVH_SSE;
    case RT_ACCEL_BVH_SCALAR:
        return RT_WORLD_BVH_SCALAR;
    default:
        return RT_WORLD_BVH;
    }
}

int rt_accel_new(rt_accel **out, const rt_scene *s, rt_accel_kind kind)
{
    return rt_accel_new_span(out, s, kind, 0.0, 1.0);
}

int rt_accel_new_span(rt_accel **out, const rt_scene *s, rt_accel_kind kind, double t_lo, double t_hi)
{
    *out = NULL;
    rt_accel *a = calloc(1, sizeof *a);
    if (!a)
        return RT_ENOMEM;
    a->kind = kind;
    a->scene = s;
    int st = RT_OK;
    /* A book-2 scene's static spheres are in the world's tree, which is
     * what its path loop walks: no sphere BVH (rt_accel_closest answers
     * by brute force, which finds the same hits). */
    const int book2 = rt_scene_is_book2(s);
    switch (kind) {
    case RT_ACCEL_BVH:
    case RT_ACCEL_BVH_SCALAR:
    case RT_ACCEL_BVH_SSE:
        if (!book2)
            st = rt_bvh_build(&a->bvh, s);
        break;
    case RT_ACCEL_BRUTE:
        break;
    case RT_ACCEL_EMBREE:
#ifdef RT_HAVE_EMBREE
        st = rt_embree_build(&a->embree, s);
#else
        st = RT_EUNSUPPORTED;
#endif
        break;
    default:
        st = RT_EINVAL;
    }
    if (!st && book2)
        st = rt_world_build(&a->world, s, world_mode(kind), t_lo, t_hi);
    if (!st && a->world)
        st = rt_lights_build(&a->lights, s, RT_LIGHTS_RULE);
    if (st) {
        rt_accel_free(a);
        return st;
    }
    *out = a;
    return RT_OK;
}

void rt_accel_free(rt_accel *a)
{
    if (!a)
        return;
    rt_bvh_free(a->bvh);
    rt_world_free(a->world);
    rt_lights_free(a->lights);
#ifdef RT_HAVE_EMBREE
    rt_embree_free(a->embree);
#endif
    free(a);
}

static int brute_closest(const rt_scene *s, const rt_ray *ray, double tmin, double tmax, rt_hit *hit)
{
    const double a = rt_v3_len2(ray->dir);
    double closest = tmax;
    uint32_t best = UINT32_MAX;
    for (uint32_t i = 0; i < s->n_spheres; i++) {
        const rt_sphere *sp = &s->spheres[i];
        rt_sphere_closer(sp->center, sp->radius * sp->radius, i, ray, a, tmin, &closest, &best);
    }
    if (best == UINT32_MAX)
        return 0;
    hit->t = closest;
    hit->prim = best;
    return 1;
}

int rt_accel_closest(const rt_accel *a, const rt_ray *ray, double tmin, double tmax, rt_hit *hit)
{
    switch (a->bvh || a->kind == RT_ACCEL_EMBREE ? a->kind : RT_ACCEL_BRUTE) {
    case RT_ACCEL_BVH:
        return rt_bvh_closest(a->bvh, ray, tmin, tmax, hit);
    case RT_ACCEL_BVH_SCALAR:
        return rt_bvh_closest_portable(a->bvh, ray, tmin, tmax, hit);
    case RT_ACCEL_BVH_SSE:
        return rt_bvh_closest_sse(a->bvh, ray, tmin, tmax, hit);
#ifdef RT_HAVE_EMBREE
    case RT_ACCEL_EMBREE:
        return rt_embree_closest(a->embree, a->scene, ray, tmin, tmax, hit);
#endif
    default:
        return brute_closest(a->scene, ray, tmin, tmax, hit);
    }
}

const char *rt_accel_name(rt_accel_kind kind)
{
    switch (kind) {
    case RT_ACCEL_BVH:
        return "bvh";
    case RT_ACCEL_BRUTE:
        return "brute";
    case RT_ACCEL_EMBREE:
        return "embree";
    case RT_ACCEL_BVH_SCALAR:
        return "bvh-scalar";
    case RT_ACCEL_BVH_SSE:
        return "bvh-sse";
    }
    return "?";
}

int rt_accel_parse(const char *name)
{
    if (!strcmp(name, "bvh"))
        return RT_ACCEL_BVH;
    if (!strcmp(name, "brute"))
        return RT_ACCEL_BRUTE;
    if (!strcmp(name, "embree"))
        return RT_ACCEL_EMBREE;
    if (!strcmp(name, "bvh-scalar"))
        return RT_ACCEL_BVH_SCALAR;
    if (!strcmp(name, "bvh-sse"))
        return RT_ACCEL_BVH_SSE;
    return -1;
}

size_t rt_accel_bytes(const rt_accel *a)
{
    return sizeof *a + (a->bvh ? rt_bvh_bytes(a->bvh) : 0) + (a->world ? rt_world_bytes(a->world) : 0) +
           rt_lights_bytes(a->lights);
}

const struct rt_world *rt_accel_world(const rt_accel *a) { return a->world; }

const struct rt_lights *rt_accel_lights(const rt_accel *a) { return a->lights; }

uint32_t rt_accel_flat_quads(const rt_accel *a)
{
    return a->kind == RT_ACCEL_BVH && a->world ? rt_world_flat_quads(a->world) : 0;
}

const char *rt_accel_box_test(const rt_accel *a)
{
    const char *baseline = RT_BVH_HAVE_SSE2 ? "sse2" : "portable";
    switch (a->kind) {
    case RT_ACCEL_BVH:
        if (!a->bvh) /* a book-2 scene: the world's tree, or its flat test (no boxes) */
            return rt_accel_flat_quads(a)                      ? NULL
                   : a->world && rt_world_uses_avx(a->world) ? "avx"
                                                               : baseline;
        return rt_bvh_uses_avx(a->bvh) ? "avx" : baseline;
    case RT_ACCEL_BVH_SSE:
        return baseline;
    case RT_ACCEL_BVH_SCALAR:
        return "portable";
    default:
        return NULL;
    }
}

const struct rt_bvh *rt_accel_bvh_avx(const rt_accel *a)
{
    return a->kind == RT_ACCEL_BVH && a->bvh && rt_bvh_uses_avx(a->bvh) ? a->bvh : NULL;
}

const struct rt_bvh *rt_accel_bvh(const rt_accel *a)
{
    return a->bvh;
}
