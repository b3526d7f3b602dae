/* tiles.c - camera rays' candidate lists by tiles of pixels (tiles.h).
 *
 * The geometry, in the camera's terms (camera.c): a camera ray leaves
 * O + e, where O is the lens centre and e a lens offset (|e| <= lens_radius,
 * at right angles to the view), towards a target Q on the focus plane, at
 * depth f in front of O. Its point at t is
 *     X(t) = O + e + t (Q - O - e) = [O + t (Q - O)] + (1 - t) e,
 * so it lies within |1 - t| lens_radius of the pinhole ray from O through Q
 * at the same t, and at depth t f. An item whose depths span [d0, d1] can
 * only be met at a t in [d0 / f, d1 / f], and only by a ray whose pinhole
 * ray comes within M of it, M the largest |1 - t| lens_radius over those t
 * (the callers put it in the item's reach, with their margins). The
 * pinhole rays of a tile's pixels fill the pyramid from O through the
 * tile's footprint on the focus plane. */
#include "tiles.h"

#include <math.h>
#include <stdlib.h>

#include "status.h"

#define SUPER 8 /* tiles per side of the blocks whose lists the tiles' lists are taken from */

double rt_tiles_focus(const rt_camera *cam)
{
    const double f = rt_v3_dot(rt_v3_sub(cam->lower_left, cam->origin), rt_v3_neg(cam->w));
    return f > 0.0 && isfinite(f) ? f : 0.0;
}

/* The inward unit normals of the four side planes of the pyramid from the
 * lens centre through the targets lower_left + s horizontal + t vertical,
 * s in [s0, s1], t in [t0, t1]. */
static void pyramid_st(const rt_camera *cam, double s0, double s1, double t0, double t1, rt_vec3 n[4])
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

/* The pixels' targets: s and t of the camera over pixels [x0, x1] x
 * [y0, y1], as path.h's path_start (book 1) or path2_start.h (book 2)
 * map a pixel and its jitter in [0, 1). */
typedef struct frame {
    const rt_camera *cam;
    int book2;
    double W, H;
} frame;

static void pyramid(const frame *F, uint32_t x0, uint32_t x1, uint32_t y0, uint32_t y1, rt_vec3 n[4])
{
    if (F->book2) {
        pyramid_st(F->cam, x0 / F->W, (x1 + 1) / F->W, 1.0 - (y1 + 1) / F->H, 1.0 - y0 / F->H, n);
    } else {
        const double dw = F->W > 1 ? F->W - 1 : 1, dh = F->H > 1 ? F->H - 1 : 1;
        pyramid_st(F->cam, x0 / dw, (x1 + 1) / dw, (F->H - 1 - y1) / dh, (F->H - y0) / dh, n);
    }
}

/* Whether the item reaches into the pyramid of inward normals n: its
 * corner farthest along each normal within its reach of the plane. */
static int reaches(const rt_vec3 n[4], const rt_tile_item *g)
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

/* f rounded down to a float (a list's bound must never rise). */
static float float_below(double f)
{
    float v = (float)f;
    return (double)v > f ? nextafterf(v, -INFINITY) : v;
}

static int by_lo(const void *pa, const void *pb)
{
    const rt_tile_item *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    return a->id < b->id ? -1 : a->id > b->id;
}

/* Tile (tx, ty)'s list from its block's items (block: indices in g). */
static int tile_list(rt_tiles *l, size_t *cap, const frame *F, const rt_tile_item *g, const uint32_t *block,
                     uint32_t nblock, int32_t max, uint32_t tx, uint32_t ty)
{
    const uint32_t T = 1u << l->shift, W = (uint32_t)F->W, H = (uint32_t)F->H;
    rt_vec3 nt[4];
    pyramid(F, tx * T, ((tx + 1) * T < W ? (tx + 1) * T : W) - 1, ty * T, ((ty + 1) * T < H ? (ty + 1) * T : H) - 1,
            nt);
    if (*cap - l->n_cand < (size_t)max + 1) {
        rt_tile_entry *grown = realloc(l->cand, 2 * *cap * sizeof *l->cand);
        if (!grown)
            return RT_ENOMEM;
        l->cand = grown;
        *cap *= 2;
    }
    int32_t count = 0;
    for (uint32_t k = 0; k < nblock && count <= max; k++)
        if (reaches(nt, &g[block[k]]))
            l->cand[l->n_cand + count++] = (rt_tile_entry){float_below(g[block[k]].lo), g[block[k]].id};
    const uint32_t t = ty * l->tiles_x + tx;
    l->tile[t].first = (uint32_t)l->n_cand;
    l->tile[t].n = count <= max ? count : -1;
    if (count <= max)
        l->n_cand += (size_t)count;
    return RT_OK;
}

int rt_tiles_build(rt_tiles *l, const rt_camera *cam, int book2_pixels, uint32_t width, uint32_t height,
                   rt_tile_item *g, uint32_t n, int32_t cap)
{
    *l = (rt_tiles){0};
    if (!width || !height || !rt_tiles_focus(cam))
        return RT_EINVAL;
    l->shift = 3; /* RT_TILES_SIZE, larger for images of more than RT_TILES_MAX tiles */
    for (;; l->shift++) {
        const uint32_t T = 1u << l->shift;
        l->tiles_x = (uint32_t)(((uint64_t)width + T - 1) >> l->shift);
        l->tiles_y = (uint32_t)(((uint64_t)height + T - 1) >> l->shift);
        if ((uint64_t)l->tiles_x * l->tiles_y <= RT_TILES_MAX)
            break;
    }
    size_t room = 1024;
    uint32_t *block = malloc((n ? n : 1) * sizeof *block);
    l->tile = malloc((size_t)l->tiles_x * l->tiles_y * sizeof *l->tile);
    l->cand = malloc(room * sizeof *l->cand);
    int st = block && l->tile && l->cand ? RT_OK : RT_ENOMEM;
    qsort(g, n, sizeof *g, by_lo);
    /* each block of SUPER x SUPER tiles from all the items, each tile from
     * its block's, so each keeps the order by lo */
    const frame F = {cam, book2_pixels, width, height};
    const uint32_t T = 1u << l->shift;
    for (uint32_t by = 0; !st && by < l->tiles_y; by += SUPER)
        for (uint32_t bx = 0; !st && bx < l->tiles_x; bx += SUPER) {
            const uint32_t tx1 = bx + SUPER < l->tiles_x ? bx + SUPER : l->tiles_x;
            const uint32_t ty1 = by + SUPER < l->tiles_y ? by + SUPER : l->tiles_y;
            rt_vec3 nb[4];
            pyramid(&F, bx * T, (tx1 * T < width ? tx1 * T : width) - 1, by * T, (ty1 * T < height ? ty1 * T : height) - 1,
                    nb);
            uint32_t nblock = 0;
            for (uint32_t j = 0; j < n; j++)
                if (reaches(nb, &g[j]))
                    block[nblock++] = j;
            for (uint32_t ty = by; !st && ty < ty1; ty++)
                for (uint32_t tx = bx; !st && tx < tx1; tx++)
                    st = tile_list(l, &room, &F, g, block, nblock, cap, tx, ty);
        }
    free(block);
    return st;
}

void rt_tiles_free(rt_tiles *l)
{
    free(l->tile);
    free(l->cand);
    *l = (rt_tiles){0};
}

size_t rt_tiles_bytes(const rt_tiles *l)
{
    return (size_t)l->tiles_x * l->tiles_y * sizeof *l->tile + l->n_cand * sizeof *l->cand;
}

void rt_tiles_stats(const rt_tiles *l, uint32_t *tiles, uint32_t *listed, size_t *candidates)
{
    *tiles = l->tiles_x * l->tiles_y;
    *listed = 0;
    for (uint32_t t = 0; t < *tiles; t++)
        *listed += l->tile[t].n >= 0;
    *candidates = l->n_cand;
}
