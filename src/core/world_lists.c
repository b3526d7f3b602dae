/* world_lists.c - candidate lists for the book-2 loop's camera rays:
 * tiles.h's lists, whose items are the world's quads, moving spheres and
 * spheres, each by its box. An item is listed for a tile unless its box
 * lies beyond one of the pyramid's four side planes by more than the lens's
 * reach and a margin of 1e-6 of the distances (its corner farthest along
 * the plane's inward normal tells). A camera ray tests its tile's items by
 * rt_world_test_item's rule, which does not depend on the order, so it is
 * the walk's and brute force's hit to the bit. */
#include "world_internal.h"

#include <math.h>
#include <stdlib.h>

#include "camera.h"
#include "status.h"
#include "tiles.h"

#define CAP 24 /* longer lists: the tile's rays walk the tree */

struct rt_world_lists {
    rt_tiles tiles; /* entries' ids: the world's items */
};

/* The items in front of the lens, with the least t at which a camera ray
 * can meet their boxes; their count. */
static uint32_t items_in_front(const rt_world *w, const rt_camera *cam, double f, rt_tile_item *g)
{
    const rt_vec3 o = cam->origin, fwd = rt_v3_neg(cam->w);
    const double lr = fabs(cam->lens_radius);
    uint32_t live = 0;
    for (uint32_t i = 0; i < w->nitems; i++) {
        const wbox b = rt_world_item_box(w, i);
        const double rlo[3] = {b.lo[0] - o.x, b.lo[1] - o.y, b.lo[2] - o.z};
        const double rhi[3] = {b.hi[0] - o.x, b.hi[1] - o.y, b.hi[2] - o.z};
        const double fw[3] = {fwd.x, fwd.y, fwd.z};
        double dmin = 0, dmax = 0, far2 = 0;
        for (int k = 0; k < 3; k++) {
            dmin += fw[k] * (fw[k] > 0 ? rlo[k] : rhi[k]);
            dmax += fw[k] * (fw[k] > 0 ? rhi[k] : rlo[k]);
            const double e = fmax(fabs(rlo[k]), fabs(rhi[k]));
            far2 += e * e;
        }
        const double margin = 1e-6 * sqrt(far2) + 1e-9;
        if (!(dmax + margin > 0.0)) /* behind the lens */
            continue;
        const double tlo = (dmin - margin) / f, thi = (dmax + margin) / f;
        const double lens = lr * fmax(fabs(1.0 - (tlo > 0.0 ? tlo : 0.0)), fabs(1.0 - thi));
        g[live] = (rt_tile_item){.lo = tlo, .id = i, .reach = lens + margin};
        for (int k = 0; k < 3; k++)
            g[live].rlo[k] = rlo[k], g[live].rhi[k] = rhi[k];
        live++;
    }
    return live;
}

int rt_world_lists_build(rt_world_lists **out, const rt_world *w, const struct rt_camera *cam, int book2_pixels,
                         uint32_t width, uint32_t height)
{
    *out = NULL;
    const double f = rt_tiles_focus(cam);
    if (!width || !height || !f)
        return RT_EINVAL;
    rt_world_lists *l = calloc(1, sizeof *l);
    rt_tile_item *g = malloc((w->nitems ? w->nitems : 1) * sizeof *g);
    int st = l && g ? RT_OK : RT_ENOMEM;
    if (!st)
        st = rt_tiles_build(&l->tiles, cam, book2_pixels, width, height, g, items_in_front(w, cam, f, g), CAP);
    free(g);
    if (st) {
        rt_world_lists_free(l);
        return st;
    }
    *out = l;
    return RT_OK;
}

void rt_world_lists_free(rt_world_lists *l)
{
    if (!l)
        return;
    rt_tiles_free(&l->tiles);
    free(l);
}

size_t rt_world_lists_bytes(const rt_world_lists *l) { return l ? sizeof *l + rt_tiles_bytes(&l->tiles) : 0; }

void rt_world_lists_stats(const rt_world_lists *l, uint32_t *tiles, uint32_t *listed, size_t *candidates)
{
    rt_tiles_stats(&l->tiles, tiles, listed, candidates);
}

int32_t rt_world_lists_tile(const rt_world_lists *l, uint32_t x, uint32_t y, uint32_t *first)
{
    return rt_tiles_tile(&l->tiles, x, y, first);
}

int rt_world_closest_listed(const rt_world *w, const rt_world_lists *l, uint32_t first, int32_t n, const rt_ray *ray,
                            double time, double tmin, double tmax, rt_whit *hit)
{
    double best_t = tmax;
    uint32_t best = UINT32_MAX;
    const rt_tile_entry *e = l->tiles.cand + first;
    for (int32_t i = 0; i < n; i++) {
        if (e[i].lo > best_t) /* by lo: no item from here on can be as near */
            break;
        rt_world_test_item(w, e[i].id, ray, time, tmin, &best_t, &best);
    }
    return rt_world_hit_of(w, best_t, best, hit);
}
