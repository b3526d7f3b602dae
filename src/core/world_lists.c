/* world_lists.c - candidate lists for the book-2 loop's camera rays: book
 * 1's camera-ray lists (primary.c) for the world's quads, moving spheres
 * and spheres.
 *
 * Every camera ray of a tile of pixels lies in the pyramid from the lens
 * centre through the tile's footprint on the focus plane, widened by the
 * lens (primary.c has the geometry: a ray's point at t has depth t f and
 * lies within |1 - t| lens_radius of its pinhole ray). An item is listed
 * for a tile unless its box lies beyond one of the pyramid's four side
 * planes by more than the lens's reach and a margin of 1e-6 of the
 * distances (its corner farthest along the plane's inward normal tells),
 * and the lists keep the items in order of the least t at which a camera
 * ray can meet their boxes. A camera ray tests its tile's items in that
 * order and stops at the first whose least t is beyond its closest hit:
 * no walk. The answer is rt_world_test_item's rule over the items tested,
 * which does not depend on the order, and an item left out can neither be
 * hit nor be closer, so it is the walk's and brute force's hit to the bit.
 * Tiles whose list would be long go to the walk. */
#include "world_internal.h"

#include <math.h>
#include <stdlib.h>

#include "camera.h"
#include "primary.h"
#include "status.h"

#define CAP 24  /* longer lists: the tile's rays walk the tree */
#define SUPER 8 /* tiles per side of the blocks whose lists the tiles' lists are taken from */

typedef struct entry {
    float lo; /* no camera ray of the tile meets the item's box at a t below it (rounded down) */
    uint32_t item;
} entry;

struct rt_world_lists {
    uint32_t tiles_x, tiles_y, shift; /* a tile is 2^shift pixels square */
    struct {
        uint32_t first; /* in cand */
        int32_t n;      /* items in the list; -1: the tile has none */
    } *tile;
    entry *cand;
    size_t n_cand, cap;
};

/* An item as the lists see it: its box relative to the lens centre, the
 * least t at which a camera ray can meet it, and how far beyond a side
 * plane it can lie and still be met. */
typedef struct geom {
    double lo;
    uint32_t item;
    double rlo[3], rhi[3];
    double reach;
} geom;

static int by_lo(const void *pa, const void *pb)
{
    const geom *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    return a->item < b->item ? -1 : a->item > b->item;
}

/* The pixels' targets: s and t of the camera (camera.c) over pixels
 * [x0, x1] x [y0, y1], as path2.c's start2 maps a pixel and its jitter in
 * [0, 1). */
typedef struct frame {
    const rt_camera *cam;
    int book2;
    double W, H;
} frame;

static void pyramid(const frame *F, uint32_t x0, uint32_t x1, uint32_t y0, uint32_t y1, rt_vec3 n[4])
{
    if (F->book2)
        rt_primary_pyramid(F->cam, x0 / F->W, (x1 + 1) / F->W, 1.0 - (y1 + 1) / F->H, 1.0 - y0 / F->H, n);
    else {
        const double dw = F->W > 1 ? F->W - 1 : 1, dh = F->H > 1 ? F->H - 1 : 1;
        rt_primary_pyramid(F->cam, x0 / dw, (x1 + 1) / dw, (F->H - 1 - y1) / dh, (F->H - y0) / dh, n);
    }
}

/* Whether the item's box reaches into the pyramid of inward normals n. */
static int reaches(const rt_vec3 n[4], const geom *g)
{
    for (int k = 0; k < 4; k++) {
        const double d = n[k].x * (n[k].x > 0 ? g->rhi[0] : g->rlo[0]) +
                         n[k].y * (n[k].y > 0 ? g->rhi[1] : g->rlo[1]) +
                         n[k].z * (n[k].z > 0 ? g->rhi[2] : g->rlo[2]);
        if (d < -g->reach)
            return 0;
    }
    return 1;
}

/* The items in front of the lens, by the least t at which a camera ray can
 * meet their boxes; their count. */
static uint32_t items_in_front(const rt_world *w, const rt_camera *cam, double f, geom *g)
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
        g[live] = (geom){.lo = tlo, .item = i, .reach = lens + margin};
        for (int k = 0; k < 3; k++)
            g[live].rlo[k] = rlo[k], g[live].rhi[k] = rhi[k];
        live++;
    }
    qsort(g, live, sizeof *g, by_lo);
    return live;
}

/* Tile (tx, ty)'s list from its block's items (block: indices in g). */
static int tile_list(rt_world_lists *l, const frame *F, const geom *g, const uint32_t *block, uint32_t nblock,
                     uint32_t tx, uint32_t ty)
{
    const uint32_t T = 1u << l->shift, W = (uint32_t)F->W, H = (uint32_t)F->H;
    rt_vec3 nt[4];
    pyramid(F, tx * T, ((tx + 1) * T < W ? (tx + 1) * T : W) - 1, ty * T, ((ty + 1) * T < H ? (ty + 1) * T : H) - 1,
            nt);
    if (l->cap - l->n_cand < CAP + 1) {
        entry *grown = realloc(l->cand, 2 * l->cap * sizeof *l->cand);
        if (!grown)
            return RT_ENOMEM;
        l->cand = grown;
        l->cap *= 2;
    }
    int32_t count = 0;
    for (uint32_t k = 0; k < nblock && count <= CAP; k++)
        if (reaches(nt, &g[block[k]]))
            l->cand[l->n_cand + count++] = (entry){rt_primary_float_below(g[block[k]].lo), g[block[k]].item};
    const uint32_t t = ty * l->tiles_x + tx;
    l->tile[t].first = (uint32_t)l->n_cand;
    l->tile[t].n = count <= CAP ? count : -1;
    if (count <= CAP)
        l->n_cand += (size_t)count;
    return RT_OK;
}

int rt_world_lists_build(rt_world_lists **out, const rt_world *w, const struct rt_camera *cam, int book2_pixels,
                         uint32_t width, uint32_t height)
{
    *out = NULL;
    const double f = rt_v3_dot(rt_v3_sub(cam->lower_left, cam->origin), rt_v3_neg(cam->w));
    if (!width || !height || !(f > 0.0) || !isfinite(f))
        return RT_EINVAL;
    rt_world_lists *l = calloc(1, sizeof *l);
    geom *g = malloc((w->nitems ? w->nitems : 1) * sizeof *g);
    uint32_t *block = malloc((w->nitems ? w->nitems : 1) * sizeof *block);
    int st = l && g && block ? RT_OK : RT_ENOMEM;
    if (!st) {
        l->shift = 3; /* 8 x 8 pixels, larger for images of more than 65,536 tiles */
        for (;; l->shift++) {
            const uint32_t T = 1u << l->shift;
            l->tiles_x = (uint32_t)(((uint64_t)width + T - 1) >> l->shift);
            l->tiles_y = (uint32_t)(((uint64_t)height + T - 1) >> l->shift);
            if ((uint64_t)l->tiles_x * l->tiles_y <= 65536u)
                break;
        }
        l->cap = 1024;
        l->tile = malloc((size_t)l->tiles_x * l->tiles_y * sizeof *l->tile);
        l->cand = malloc(l->cap * sizeof *l->cand);
        st = l->tile && l->cand ? RT_OK : RT_ENOMEM;
    }
    const frame F = {cam, book2_pixels, width, height};
    const uint32_t live = st ? 0 : items_in_front(w, cam, f, g), T = 1u << (l ? l->shift : 0);
    for (uint32_t by = 0; !st && by < l->tiles_y; by += SUPER)
        for (uint32_t bx = 0; !st && bx < l->tiles_x; bx += SUPER) {
            const uint32_t tx1 = bx + SUPER < l->tiles_x ? bx + SUPER : l->tiles_x;
            const uint32_t ty1 = by + SUPER < l->tiles_y ? by + SUPER : l->tiles_y;
            rt_vec3 nb[4];
            pyramid(&F, bx * T, (tx1 * T < width ? tx1 * T : width) - 1, by * T, (ty1 * T < height ? ty1 * T : height) - 1,
                    nb);
            uint32_t nblock = 0;
            for (uint32_t j = 0; j < live; j++)
                if (reaches(nb, &g[j]))
                    block[nblock++] = j;
            for (uint32_t ty = by; !st && ty < ty1; ty++)
                for (uint32_t tx = bx; !st && tx < tx1; tx++)
                    st = tile_list(l, &F, g, block, nblock, tx, ty);
        }
    free(g);
    free(block);
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
    free(l->tile);
    free(l->cand);
    free(l);
}

size_t rt_world_lists_bytes(const rt_world_lists *l)
{
    return l ? sizeof *l + (size_t)l->tiles_x * l->tiles_y * sizeof *l->tile + l->n_cand * sizeof *l->cand : 0;
}

void rt_world_lists_stats(const rt_world_lists *l, uint32_t *tiles, uint32_t *listed, size_t *candidates)
{
    *tiles = l->tiles_x * l->tiles_y;
    *listed = 0;
    for (uint32_t t = 0; t < *tiles; t++)
        *listed += l->tile[t].n >= 0;
    *candidates = l->n_cand;
}

int32_t rt_world_lists_tile(const rt_world_lists *l, uint32_t x, uint32_t y, uint32_t *first)
{
    const uint32_t t = (y >> l->shift) * l->tiles_x + (x >> l->shift);
    *first = l->tile[t].first;
    return l->tile[t].n;
}

int rt_world_closest_listed(const rt_world *w, const rt_world_lists *l, uint32_t first, int32_t n, const rt_ray *ray,
                            double time, double tmin, double tmax, rt_whit *hit)
{
    double best_t = tmax;
    uint32_t best = UINT32_MAX;
    const entry *e = l->cand + first;
    for (int32_t i = 0; i < n; i++) {
        if (e[i].lo > best_t) /* by lo: no item from here on can be as near */
            break;
        rt_world_test_item(w, e[i].item, ray, time, tmin, &best_t, &best);
    }
    return rt_world_hit_of(w, best_t, best, hit);
}
