/* primary.c - candidate lists for camera rays over the spheres (see
 * primary.h; the geometry and the lists are tiles.c's). A sphere of centre
 * c (depth dc) and radius r can only be met at a t in [(dc - r) / f,
 * (dc + r) / f], and only by a ray whose pinhole ray comes within r + M of
 * c (M the lens's reach over those t). Every bound is widened by a margin
 * of 1e-6 of the distances involved, against rounding of at most about
 * 2e-8 of them (a ray's construction is good to a few ulps; the sphere
 * test's root loses half its digits only for a grazing ray, sqrt(2^-52) ~
 * 1.5e-8 of its t), so no sphere that a camera ray can hit is ever left out,
 * and none is skipped while it could still be closer. */
#include "primary.h"

#include <math.h>
#include <stdlib.h>

#include "sphere.h"
#include "status.h"

#define PRIMARY_CAP 16 /* longer lists: the tile's rays go to the BVH */

int rt_primary_build(rt_primary **out, const rt_scene *s, const rt_camera *cam, uint32_t width, uint32_t height)
{
    *out = NULL;
    const double f = rt_tiles_focus(cam), lr = fabs(cam->lens_radius);
    if (!width || !height || !f)
        return RT_EINVAL;
    const rt_vec3 fwd = rt_v3_neg(cam->w);
    const uint32_t n = s->n_spheres;
    rt_primary *p = calloc(1, sizeof *p);
    rt_tile_item *g = malloc((n ? n : 1) * sizeof *g);
    int st = p && g ? RT_OK : RT_ENOMEM;
    /* the spheres in front of the lens (the others cannot be hit) */
    uint32_t live = 0;
    for (uint32_t i = 0; i < n && !st; i++) {
        const rt_sphere *sp = &s->spheres[i];
        const rt_vec3 d = rt_v3_sub(sp->center, cam->origin);
        const double r = fabs(sp->radius), dc = rt_v3_dot(d, fwd);
        const double margin = 1e-6 * (sqrt(rt_v3_len2(d)) + r) + 1e-9;
        if (dc + r + margin <= 0.0)
            continue;
        double tlo = (dc - r - margin) / f, thi = (dc + r + margin) / f;
        const double lens = lr * fmax(fabs(1.0 - (tlo > 0.0 ? tlo : 0.0)), fabs(1.0 - thi));
        g[live++] = (rt_tile_item){.lo = tlo, .id = i, .rlo = {d.x, d.y, d.z}, .rhi = {d.x, d.y, d.z},
                                   .reach = r + lens + margin};
    }
    if (!st) {
        p->spheres = s->spheres;
        st = rt_tiles_build(&p->tiles, cam, 0, width, height, g, live, PRIMARY_CAP);
    }
    free(g);
    if (st) {
        rt_primary_free(p);
        return st;
    }
    *out = p;
    return RT_OK;
}

int rt_primary_closest(const rt_primary *p, uint32_t first, int32_t n, const rt_ray *ray, double tmin, double tmax,
                       rt_hit *hit)
{
    const double a = rt_v3_len2(ray->dir);
    double closest = tmax;
    uint32_t best = UINT32_MAX;
    const rt_tile_entry *e = p->tiles.cand + first;
    for (int32_t i = 0; i < n; i++) {
        if (e[i].lo > closest) /* sorted by lo: no sphere from here on can be as close */
            break;
        const rt_sphere *sp = &p->spheres[e[i].id];
        /* as brute force tests it (accel.c): the same bits */
        rt_sphere_closer(sp->center, sp->radius * sp->radius, e[i].id, ray, a, tmin, &closest, &best);
    }
    if (best == UINT32_MAX)
        return 0;
    hit->t = closest;
    hit->prim = best;
    return 1;
}

void rt_primary_free(rt_primary *p)
{
    if (!p)
        return;
    rt_tiles_free(&p->tiles);
    free(p);
}

size_t rt_primary_bytes(const rt_primary *p) { return p ? sizeof *p + rt_tiles_bytes(&p->tiles) : 0; }

void rt_primary_stats(const rt_primary *p, uint32_t *tiles, uint32_t *listed, size_t *candidates)
{
    rt_tiles_stats(&p->tiles, tiles, listed, candidates);
}
