/* primary.c - candidate lists for camera rays (see primary.h).
 *
 * The geometry, in the camera's terms (camera.c): a camera ray leaves
 * O + e, where O is the lens centre and e a lens offset (|e| <= lens_radius,
 * at right angles to the view), towards a target Q on the focus plane, at
 * depth f in front of O. Its point at t is
 *     X(t) = O + e + t (Q - O - e) = [O + t (Q - O)] + (1 - t) e,
 * so it lies within |1 - t| lens_radius of the pinhole ray from O through Q
 * at the same t, and at depth t f. A sphere of centre c (depth dc) and radius
 * r can therefore only be met at a t in [(dc - r) / f, (dc + r) / f], and only
 * by a ray whose pinhole ray comes within r + M of c, where M is the largest
 * |1 - t| lens_radius over those t. The pinhole rays of a tile's pixels fill
 * the pyramid from O through the tile's footprint on the focus plane; a
 * sphere is listed unless it lies beyond one of the pyramid's four side
 * planes by more than r + M. Every bound is widened by a margin of 1e-6 of
 * the distances involved, against rounding of at most about 2e-8 of them (a
 * ray's construction is good to a few ulps; the sphere test's root loses
 * half its digits only for a grazing ray, sqrt(2^-52) ~ 1.5e-8 of its t), so
 * no sphere that a camera ray can hit is ever left out, and none is skipped
 * while it could still be closer. */
#include "primary.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sphere.h"
#include "status.h"

#ifndef PRIMARY_CAP
#define PRIMARY_CAP 16 /* longer lists: the tile's rays go to the BVH */
#endif
#define SUPER 8 /* tiles per side of the blocks whose lists the tiles' lists are taken from */

/* A sphere as the lists see it, computed once: the least t at which a
 * camera ray can meet it, its index in the scene, its centre relative to the
 * lens centre, and how far beyond a side plane of a pyramid it can lie and
 * still be met (its radius, the lens's reach over its depths, a margin). */
typedef struct geom {
    double lo;
    uint32_t index;
    rt_vec3 rel;
    double reach;
} geom;

static int by_lo(const void *pa, const void *pb)
{
    const geom *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    return a->index < b->index ? -1 : a->index > b->index;
}

typedef struct frame {
    const rt_camera *cam;
    double dw, dh; /* the divisors of the pixel coordinates (path.h's path_start) */
    uint32_t width, height;
} frame;

/* The inward unit normals of the side planes of the pyramid from the lens
 * centre through the footprint of pixels [x0, x1] x [y0, y1]. */
static void pyramid(const frame *F, uint32_t x0, uint32_t x1, uint32_t y0, uint32_t y1, rt_vec3 n[4])
{
    rt_primary_pyramid(F->cam, x0 / F->dw, (x1 + 1) / F->dw, (F->height - 1 - y1) / F->dh, (F->height - y0) / F->dh,
                       n);
}

void rt_primary_pyramid(const rt_camera *cam, double s0, double s1, double t0, double t1, rt_vec3 n[4])
{
    const rt_vec3 base = rt_v3_sub(cam->lower_left, cam->origin), h = cam->horizontal, v = cam->vertical;
    n[0] = rt_v3_cross(v, rt_v3_add(base, rt_v3_scale(h, s0)));
    n[1] = rt_v3_cross(v, rt_v3_add(base, rt_v3_scale(h, s1)));
    n[2] = rt_v3_cross(h, rt_v3_add(base, rt_v3_scale(v, t0)));
    n[3] = rt_v3_cross(h, rt_v3_add(base, rt_v3_scale(v, t1)));
    const rt_vec3 inward[4] = {h, rt_v3_neg(h), v, rt_v3_neg(v)};
    for (int k = 0; k < 4; k++) {
        if (rt_v3_dot(n[k], inward[k]) < 0.0)
            n[k] = rt_v3_neg(n[k]);
        n[k] = rt_v3_unit(n[k]);
    }
}

/* Whether the sphere reaches into the pyramid of inward normals n. */
static inline int reaches(const rt_vec3 n[4], const geom *g)
{
    for (int k = 0; k < 4; k++)
        if (rt_v3_dot(n[k], g->rel) < -g->reach)
            return 0;
    return 1;
}

float rt_primary_float_below(double f)
{
    float v = (float)f;
    return (double)v > f ? nextafterf(v, -INFINITY) : v;
}

int rt_primary_build(rt_primary **out, const rt_scene *s, const rt_camera *cam, uint32_t width, uint32_t height)
{
    *out = NULL;
    if (!width || !height)
        return RT_EINVAL;
    frame F = {.cam = cam,
               .dw = width > 1 ? width - 1.0 : 1.0,
               .dh = height > 1 ? height - 1.0 : 1.0,
               .width = width,
               .height = height};
    const rt_vec3 fwd = rt_v3_neg(cam->w);
    const double f = rt_v3_dot(rt_v3_sub(cam->lower_left, cam->origin), fwd), lr = fabs(cam->lens_radius);
    if (!(f > 0.0) || !isfinite(f))
        return RT_EINVAL;
    const uint32_t n = s->n_spheres;
    rt_primary *p = calloc(1, sizeof *p);
    geom *g = malloc((n ? n : 1) * sizeof *g);
    uint32_t *block = malloc((n ? n : 1) * sizeof *block);
    int st = RT_ENOMEM;
    if (!p || !g || !block)
        goto fail;
    p->spheres = s->spheres;
    p->width = width;
    p->height = height;
    p->shift = 3; /* RT_PRIMARY_TILE */
    for (;;) {
        const uint32_t T = 1u << p->shift;
        p->tiles_x = (uint32_t)(((uint64_t)width + T - 1) >> p->shift);
        p->tiles_y = (uint32_t)(((uint64_t)height + T - 1) >> p->shift);
        if ((uint64_t)p->tiles_x * p->tiles_y <= RT_PRIMARY_MAX_TILES)
            break;
        p->shift++;
    }
    p->tile = malloc((size_t)p->tiles_x * p->tiles_y * sizeof *p->tile);
    if (!p->tile)
        goto fail;
    /* The spheres in front of the lens (the others cannot be hit), by the
     * least t at which a camera ray can meet them. */
    uint32_t live = 0;
    for (uint32_t i = 0; i < n; i++) {
        const rt_sphere *sp = &s->spheres[i];
        const rt_vec3 d = rt_v3_sub(sp->center, cam->origin);
        const double r = fabs(sp->radius), dc = rt_v3_dot(d, fwd);
        const double margin = 1e-6 * (sqrt(rt_v3_len2(d)) + r) + 1e-9;
        if (dc + r + margin <= 0.0)
            continue;
        double tlo = (dc - r - margin) / f, thi = (dc + r + margin) / f;
        const double lens = lr * fmax(fabs(1.0 - (tlo > 0.0 ? tlo : 0.0)), fabs(1.0 - thi));
        g[live++] = (geom){.lo = tlo, .index = i, .rel = d, .reach = r + lens + margin};
    }
    qsort(g, live, sizeof *g, by_lo);
    /* The lists: each block of SUPER x SUPER tiles from all the spheres, each
     * tile from its block's, so each keeps the order by lo. */
    size_t cap = 1024, used = 0;
    p->cand = malloc(cap * sizeof *p->cand);
    if (!p->cand)
        goto fail;
    const uint32_t T = 1u << p->shift;
    for (uint32_t by = 0; by < p->tiles_y; by += SUPER)
        for (uint32_t bx = 0; bx < p->tiles_x; bx += SUPER) {
            const uint32_t tx1 = bx + SUPER < p->tiles_x ? bx + SUPER : p->tiles_x;
            const uint32_t ty1 = by + SUPER < p->tiles_y ? by + SUPER : p->tiles_y;
            rt_vec3 nb[4];
            pyramid(&F, bx * T, (tx1 * T < width ? tx1 * T : width) - 1, by * T,
                    (ty1 * T < height ? ty1 * T : height) - 1, nb);
            uint32_t nblock = 0;
            for (uint32_t j = 0; j < live; j++)
                if (reaches(nb, &g[j]))
                    block[nblock++] = j;
            for (uint32_t ty = by; ty < ty1; ty++)
                for (uint32_t tx = bx; tx < tx1; tx++) {
                    rt_vec3 nt[4];
                    const uint32_t x1 = (tx + 1) * T < width ? (tx + 1) * T : width;
                    const uint32_t y1 = (ty + 1) * T < height ? (ty + 1) * T : height;
                    pyramid(&F, tx * T, x1 - 1, ty * T, y1 - 1, nt);
                    if (cap - used < PRIMARY_CAP + 1) {
                        rt_primary_entry *grown = realloc(p->cand, 2 * cap * sizeof *p->cand);
                        if (!grown)
                            goto fail;
                        p->cand = grown;
                        cap *= 2;
                    }
                    int32_t count = 0;
                    for (uint32_t k = 0; k < nblock && count <= PRIMARY_CAP; k++) {
                        const geom *q = &g[block[k]];
                        if (reaches(nt, q))
                            p->cand[used + count++] = (rt_primary_entry){rt_primary_float_below(q->lo), q->index};
                    }
                    const uint32_t t = ty * p->tiles_x + tx;
                    p->tile[t].first = (uint32_t)used;
                    p->tile[t].n = count <= PRIMARY_CAP ? count : -1;
                    if (count <= PRIMARY_CAP)
                        used += (size_t)count;
                }
        }
    p->n_cand = used;
    free(g);
    free(block);
    *out = p;
    return RT_OK;
fail:
    free(g);
    free(block);
    rt_primary_free(p);
    return st;
}

int rt_primary_closest(const rt_primary *p, uint32_t first, int32_t n, const rt_ray *ray, double tmin, double tmax,
                       rt_hit *hit)
{
    const double a = rt_v3_len2(ray->dir);
    double closest = tmax;
    uint32_t best = UINT32_MAX;
    const rt_primary_entry *e = p->cand + first;
    for (int32_t i = 0; i < n; i++) {
        if (e[i].lo > closest) /* sorted by lo: no sphere from here on can be as close */
            break;
        const rt_sphere *sp = &p->spheres[e[i].sphere];
        /* as brute force tests it (accel.c): the same bits */
        rt_sphere_closer(sp->center, sp->radius * sp->radius, e[i].sphere, ray, a, tmin, &closest, &best);
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
    free(p->tile);
    free(p->cand);
    free(p);
}

size_t rt_primary_bytes(const rt_primary *p)
{
    if (!p)
        return 0;
    return sizeof *p + (size_t)p->tiles_x * p->tiles_y * sizeof *p->tile + p->n_cand * sizeof *p->cand;
}

void rt_primary_stats(const rt_primary *p, uint32_t *tiles, uint32_t *listed, size_t *candidates)
{
    *tiles = p->tiles_x * p->tiles_y;
    *listed = 0;
    for (uint32_t t = 0; t < *tiles; t++)
        *listed += p->tile[t].n >= 0;
    *candidates = p->n_cand;
}
