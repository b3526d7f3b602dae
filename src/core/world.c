/* world.c - the world's build: quads, moving and static spheres in a
 * binary SAH tree of their boxes, collapsed into a wide tree of float boxes
 * (world_closest.c walks it); the media's spans, surface records with
 * (u, v). */
#include "world_internal.h"
#include "core_internal.h"
#include "fbox.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sphere.h"
#include "status.h"

/* Items of a leaf at most: a node of more is split even when the heuristic
 * says no. One: in a wide node a leaf takes a child slot, and its item's
 * own box is the tightest cull the box test can make. */
#define LEAF_ITEMS 1

/* A node of the binary tree (the build's): */
typedef struct wnode {
    double lo[3], hi[3];
    uint32_t first, count; /* leaf: items [first, first + count); inner: count 0, children me + 1, first */
} wnode;

typedef struct keyed {
    double key;
    uint32_t item;
} keyed;

/* The build's state: its nodes, the items' leaf order, and each axis's
 * order of the items by their boxes' centres (ord[k]: the key, then the
 * item, a total order), a node's items a segment of each; side and
 * scratch are the partition's. */
typedef struct bin {
    wnode *nodes;
    uint32_t n_nodes;
    uint32_t *items;
    keyed *ord[3], *scratch;
    uint8_t *side;
} bin;

typedef wbox box;

static void box_point(box *b, rt_vec3 p, double pad)
{
    const double c[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; k++) {
        b->lo[k] = fmin(b->lo[k], c[k] - pad);
        b->hi[k] = fmax(b->hi[k], c[k] + pad);
    }
}

wbox rt_world_item_box(const rt_world *w, uint32_t i)
{
    box b = {{DBL_MAX, DBL_MAX, DBL_MAX}, {-DBL_MAX, -DBL_MAX, -DBL_MAX}};
    if (i < w->nq) {
        const rt_quad *q = &w->s->shapes.quads.items[i];
        const double pad = 1e-4; /* a flat quad still gets a box with volume (the book's padding) */
        box_point(&b, q->q, pad);
        box_point(&b, rt_v3_add(q->q, q->u), pad);
        box_point(&b, rt_v3_add(q->q, q->v), pad);
        box_point(&b, rt_v3_add(rt_v3_add(q->q, q->u), q->v), pad);
    } else if (i < w->ns) {
        const rt_mover *m = &w->s->shapes.movers.items[i - w->nq];
        box_point(&b, m->center0, fabs(m->radius));
        box_point(&b, m->center1, fabs(m->radius));
        if (w->t_lo < 0.0) /* the points of times 0 and 1 as they are: the book's boxes, to the bit */
            box_point(&b, rt_mover_center(m, w->t_lo), fabs(m->radius));
        if (w->t_hi > 1.0)
            box_point(&b, rt_mover_center(m, w->t_hi), fabs(m->radius));
    } else {
        const rt_sphere *sp = &w->s->spheres[i - w->ns];
        box_point(&b, sp->center, fabs(sp->radius));
    }
    return b;
}

static int by_key(const void *pa, const void *pb)
{
    const keyed *a = pa, *b = pb;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    return (a->item > b->item) - (a->item < b->item);
}

static double area(const box *b)
{
    const double x = b->hi[0] - b->lo[0], y = b->hi[1] - b->lo[1], z = b->hi[2] - b->lo[2];
    return x * y + y * z + z * x;
}

static void grow(box *b, const box *o)
{
    for (int k = 0; k < 3; k++) {
        b->lo[k] = o->lo[k] < b->lo[k] ? o->lo[k] : b->lo[k];
        b->hi[k] = o->hi[k] > b->hi[k] ? o->hi[k] : b->hi[k];
    }
}

static const box EMPTY = {{DBL_MAX, DBL_MAX, DBL_MAX}, {-DBL_MAX, -DBL_MAX, -DBL_MAX}};

/* The surface area heuristic's best split of the sorted items ord[0, count)
 * (cost in box areas times items, a box test costing one item test), at
 * *at; returns its cost. rest: scratch of count boxes. */
static double best_split(const box *bx, const keyed *ord, uint32_t count, box *rest, uint32_t *at)
{
    box acc = EMPTY;
    for (uint32_t i = count; i-- > 1;) { /* rest[i]: the box of items i.. */
        grow(&acc, &bx[ord[i].item]);
        rest[i] = acc;
    }
    acc = EMPTY;
    double best = DBL_MAX;
    for (uint32_t i = 1; i < count; i++) {
        grow(&acc, &bx[ord[i - 1].item]);
        const double c = area(&acc) * i + area(&rest[i]) * (count - i);
        if (c < best) {
            best = c;
            *at = i;
        }
    }
    return best;
}

/* Axis k's order of the items [first, first + count) made the children's:
 * those of side 1 first, each side in the order it had (a stable
 * partition, so each child's segment stays sorted). */
static void partition(bin *w, int k, uint32_t first, uint32_t count)
{
    keyed *o = w->ord[k] + first;
    uint32_t n1 = 0, n0 = 0;
    for (uint32_t i = 0; i < count; i++)
        if (w->side[o[i].item])
            o[n1++] = o[i];
        else
            w->scratch[n0++] = o[i];
    memcpy(o + n1, w->scratch, n0 * sizeof *o);
}

/* Node over items [first, first + count): a leaf, or the split the surface
 * area heuristic picks among the orders of the centres on each axis (ties
 * by item, so every rank builds the same tree). The orders are sorted once
 * (build_tree) and partitioned at each split, not sorted again: the same
 * splits in O(n log n). An inner node's left child follows it; its `first`
 * is the right child. */
static int build(bin *w, const box *bx, box *rest, uint32_t first, uint32_t count)
{
    const uint32_t me = w->n_nodes++;
    box b = EMPTY;
    for (uint32_t i = first; i < first + count; i++)
        grow(&b, &bx[w->items[i]]);
    wnode *n = &w->nodes[me];
    memcpy(n->lo, b.lo, sizeof b.lo);
    memcpy(n->hi, b.hi, sizeof b.hi);
    n->first = first;
    n->count = count;
    if (count <= 1)
        return (int)me;
    double best = area(&b) * (count - 1.0); /* a leaf: all items, less the box test it saves */
    int axis = -1;
    uint32_t at = 0;
    for (int k = 0; k < 3; k++) {
        uint32_t a = 0;
        /* the split's cost, plus the two children's boxes tested */
        const double c = best_split(bx, w->ord[k] + first, count, rest, &a) + area(&b);
        if (c < best || (count > LEAF_ITEMS && axis < 0)) {
            best = c;
            axis = k;
            at = a;
        }
    }
    if (axis < 0)
        return (int)me;
    const keyed *o = w->ord[axis] + first;
    for (uint32_t i = 0; i < count; i++) {
        w->items[first + i] = o[i].item;
        w->side[o[i].item] = i < at;
    }
    for (int k = 0; k < 3; k++)
        if (k != axis)
            partition(w, k, first, count);
    build(w, bx, rest, first, at);
    const int right = build(w, bx, rest, first + at, count - at);
    w->nodes[me].first = (uint32_t)right;
    w->nodes[me].count = 0;
    return (int)me;
}

static quad_x quad_prep(const rt_quad *q)
{
    quad_x x;
    x.q = q->q;
    const rt_vec3 N = rt_v3_cross(q->u, q->v);
    x.n = rt_v3_unit(N);
    x.d = rt_v3_dot(x.n, q->q);
    const rt_vec3 w = rt_v3_scale(N, 1.0 / rt_v3_dot(N, N));
    x.ea = rt_v3_cross(q->v, w);
    x.eb = rt_v3_cross(w, q->u);
    return x;
}

/* The wide tree's node for binary node bid (world.c's build): its children
 * are the binary node's, the largest inner one opened until there are
 * WWIDTH; their boxes in float, widened by more than the rounding of box
 * and ray origin (margin_base) and rounded outward. Returns its index, or
 * -1 past RT_WORLD_DEPTH_MAX levels. */
static int collapse(rt_world *w, const wnode *bn, uint32_t bid, double margin_base, int depth)
{
    if (depth > RT_WORLD_DEPTH_MAX)
        return -1;
    const uint32_t me = w->n_nodes++;
    uint32_t kids[WWIDTH];
    int nk = 0;
    if (bn[bid].count) { /* a root that is a leaf */
        kids[nk++] = bid;
    } else {
        kids[nk++] = bid + 1;
        kids[nk++] = bn[bid].first;
    }
    while (nk < WWIDTH) {
        int open = -1;
        double open_area = -1;
        for (int k = 0; k < nk; k++) {
            const wnode *c = &bn[kids[k]];
            box b;
            memcpy(b.lo, c->lo, sizeof b.lo);
            memcpy(b.hi, c->hi, sizeof b.hi);
            if (!c->count && area(&b) > open_area) {
                open_area = area(&b);
                open = k;
            }
        }
        if (open < 0)
            break;
        const uint32_t o = kids[open];
        kids[open] = o + 1;
        kids[nk++] = bn[o].first;
    }
    wide n;
    memset(&n, 0, sizeof n);
    n.nchild = (1 << nk) - 1;
    for (int k = 0; k < WWIDTH; k++) {
        for (int a = 0; a < 3; a++) {
            n.bmin[a][k] = INFINITY;
            n.bmax[a][k] = -INFINITY;
        }
        if (k >= nk)
            continue;
        const wnode *c = &bn[kids[k]];
        for (int a = 0; a < 3; a++) {
            const double margin = 1e-6 * (1.0 + fmax(fabs(c->lo[a]), fabs(c->hi[a]))) + margin_base;
            n.bmin[a][k] = round_down(c->lo[a], margin);
            n.bmax[a][k] = round_up(c->hi[a], margin);
        }
        if (c->count) {
            n.child[k] = ~(int32_t)w->items[c->first]; /* LEAF_ITEMS 1 */
        } else {
            const int sub = collapse(w, bn, kids[k], margin_base, depth + 1);
            if (sub < 0)
                return -1;
            n.child[k] = sub;
        }
    }
    w->nodes[me] = n;
    return (int)me;
}

/* The wide tree over the items' boxes bx; RT_OK with no tree (brute force)
 * when it would be too deep. */
static int build_tree(rt_world *w, const box *bx, double extent)
{
    const uint32_t n = w->nitems;
    bin B = {malloc(2 * (size_t)n * sizeof *B.nodes), 0, w->items, {NULL, NULL, NULL}, NULL, NULL};
    for (int k = 0; k < 3; k++)
        B.ord[k] = malloc(n * sizeof *B.ord[k]);
    B.scratch = malloc(n * sizeof *B.scratch);
    B.side = malloc(n);
    box *rest = malloc(n * sizeof *rest);
    w->nodes = aligned_alloc(64, 2 * (size_t)n * sizeof *w->nodes);
    int st = B.nodes && B.ord[0] && B.ord[1] && B.ord[2] && B.scratch && B.side && rest && w->nodes ? RT_OK : RT_ENOMEM;
    if (!st) {
        for (int k = 0; k < 3; k++) {
            for (uint32_t i = 0; i < n; i++)
                B.ord[k][i] = (keyed){bx[w->items[i]].lo[k] + bx[w->items[i]].hi[k], w->items[i]};
            qsort(B.ord[k], n, sizeof *B.ord[k], by_key);
        }
        build(&B, bx, rest, 0, n);
        /* ray origins are rounded to float too: a little more than that */
        if (collapse(w, B.nodes, 0, 4.0 * extent * FLT_EPSILON, 1) < 0 || n >= (1u << 31)) {
            w->n_nodes = 0;
            w->mode = RT_WORLD_BRUTE;
        }
    }
    free(B.nodes);
    for (int k = 0; k < 3; k++)
        free(B.ord[k]);
    free(B.scratch);
    free(B.side);
    free(rest);
    return st;
}

/* The largest coordinate of the boxes and the camera. */
static double extent_of(const rt_scene *s, const box *bx, uint32_t n)
{
    const rt_vec3 c = s->camera.lookfrom;
    double e = fmax(fabs(c.x), fmax(fabs(c.y), fabs(c.z)));
    for (uint32_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            e = fmax(e, fmax(fabs(bx[i].lo[k]), fabs(bx[i].hi[k])));
    return e;
}

static void orient_hulls(rt_world *w);

/* The leaves a ray that enters the scene's box enters on average, by the
 * surface-area heuristic's rule (a box's chance to be entered is its area
 * over the scene box's): the items' boxes' areas over the scene box's.
 * The rooms of books 2 and 3 about 2 (walls as large as the room's
 * faces), scenes of objects apart about 1: world_flat.c's rule. */
static double leaves_per_ray(const box *bx, uint32_t n)
{
    box all = EMPTY;
    double sum = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        grow(&all, &bx[i]);
        sum += area(&bx[i]);
    }
    return sum / area(&all);
}

int rt_world_build(rt_world **out, const rt_scene *s, rt_world_mode mode, double t_lo, double t_hi)
{
    *out = NULL;
    rt_world *w = calloc(1, sizeof *w);
    if (!w)
        return RT_ENOMEM;
    w->s = s;
    w->mode = mode == RT_WORLD_FLAT ? RT_WORLD_BVH : mode; /* the flat test where it can, else the tree */
    w->t_lo = t_lo;
    w->t_hi = t_hi;
#if RT_BVH_HAVE_AVX
    __builtin_cpu_init();
    if (w->mode == RT_WORLD_BVH && !__builtin_cpu_supports("avx"))
        w->mode = RT_WORLD_BVH_SSE;
#else
    if (w->mode == RT_WORLD_BVH)
        w->mode = RT_WORLD_BVH_SSE;
#endif
    w->nq = s->shapes.quads.n;
    w->ns = w->nq + s->shapes.movers.n;
    w->nitems = w->ns + s->n_spheres;
    rt_perlin_init(&w->perlin, s->tex.noise_seed);
    const size_t n = w->nitems ? w->nitems : 1;
    w->quads = malloc((w->nq ? w->nq : 1) * sizeof *w->quads);
    w->items = malloc(n * sizeof *w->items);
    w->mat = malloc(n * sizeof *w->mat);
    box *bx = malloc(n * sizeof *bx);
    w->hull = malloc((s->media.hull.n ? s->media.hull.n : 1) * sizeof *w->hull);
    int st = (w->quads && w->hull && w->items && w->mat && bx) ? RT_OK : RT_ENOMEM;
    for (uint32_t i = 0; i < w->nq && !st; i++)
        w->quads[i] = quad_prep(&s->shapes.quads.items[i]);
    for (uint32_t i = 0; i < s->media.hull.n && !st; i++)
        w->hull[i] = quad_prep(&s->media.hull.items[i]);
    if (!st)
        orient_hulls(w);
    for (uint32_t i = 0; i < w->nitems && !st; i++) {
        w->items[i] = i;
        rt_whit h = {0};
        rt_world_shape(w, i, &h.kind, &h.index);
        w->mat[i] = rt_world_material(w, &h);
        bx[i] = rt_world_item_box(w, i);
    }
    const double extent = !st && w->nitems ? extent_of(s, bx, w->nitems) : 0.0;
    if (!st && w->nitems && w->mode != RT_WORLD_BRUTE)
        st = build_tree(w, bx, extent);
    if (!st && w->n_nodes)
        st = rt_world_rooms_build(w, bx, extent);
    const double leaves = !st && w->nitems ? leaves_per_ray(bx, w->nitems) : 0.0;
    free(bx);
    if (!st && w->mode == RT_WORLD_BVH)
        st = rt_world_flat_build(w, mode == RT_WORLD_FLAT, leaves);
    if (st) {
        rt_world_free(w);
        return st;
    }
    rt_world_pick(w);
    *out = w;
    return RT_OK;
}

void rt_world_free(rt_world *w)
{
    if (!w)
        return;
    free(w->quads);
    free(w->hull);
    free(w->items);
    free(w->mat);
    free(w->nodes);
    free(w->flat);
    free(w->rooms);
    free(w->room_of);
    free(w);
}

size_t rt_world_bytes(const rt_world *w)
{
    return sizeof *w + ((size_t)w->nq + w->s->media.hull.n) * sizeof *w->quads +
           (size_t)w->nitems * (sizeof *w->items + sizeof *w->mat) + (size_t)w->n_nodes * sizeof(wide) +
           (size_t)w->n_flat * sizeof(flat8) + (size_t)w->n_rooms * sizeof(room) +
           (w->room_of ? (size_t)w->s->n_spheres * sizeof *w->room_of : 0);
}

const rt_perlin *rt_world_perlin(const rt_world *w) { return &w->perlin; }

int rt_world_uses_avx(const rt_world *w)
{
    return RT_BVH_HAVE_AVX && w->n_nodes && w->mode == RT_WORLD_BVH && !w->flat;
}

uint32_t rt_world_flat_quads(const rt_world *w) { return w->flat ? w->nq : 0; }

/* Turns every medium's hull quads outward (rt_world_medium_span clips the
 * line by their planes): the normal and offset of a quad whose plane has
 * the hull's centre (the mean of its faces' centres) on its outer side
 * change sign, exactly, so each plane's crossing of a line keeps its bits,
 * and so does rt_quad_t. */
static void orient_hulls(rt_world *w)
{
    const rt_scene *s = w->s;
    for (uint32_t k = 0; k < s->media.media.n; k++) {
        const rt_medium *m = &s->media.media.items[k];
        if (m->shape == RT_MEDIUM_SPHERE || !m->count)
            continue;
        rt_vec3 c = {0, 0, 0};
        for (uint32_t i = m->first; i < m->first + m->count; i++) {
            const rt_quad *q = &s->media.hull.items[i];
            c = rt_v3_add(c, rt_v3_add(q->q, rt_v3_scale(rt_v3_add(q->u, q->v), 0.5)));
        }
        c = rt_v3_scale(c, 1.0 / m->count);
        for (uint32_t i = m->first; i < m->first + m->count; i++)
            if (rt_v3_dot(w->hull[i].n, c) > w->hull[i].d) {
                w->hull[i].n = rt_v3_neg(w->hull[i].n);
                w->hull[i].d = -w->hull[i].d;
            }
    }
}

int rt_world_medium_span(const rt_world *w, uint32_t k, const rt_ray *ray, double *t0, double *t1)
{
    const rt_medium *m = &w->s->media.media.items[k];
    if (m->shape == RT_MEDIUM_SPHERE)
        return rt_world_sphere_span(m, ray, t0, t1);
    /* A convex hull: the line is inside where it is inside every face's
     * plane, from the last plane it enters to the first it leaves (the
     * same crossings, by rt_quad_t's formula, as its first and last
     * crossing of the hull's quads, without testing the quads' edges). A
     * line along a plane (rt_quad_t's threshold) is inside all or none. */
    double lo = -DBL_MAX, hi = DBL_MAX;
    for (uint32_t i = m->first; i < m->first + m->count; i++) {
        const quad_x *q = &w->hull[i];
        const double denom = rt_v3_dot(q->n, ray->dir), off = q->d - rt_v3_dot(q->n, ray->orig);
        if (fabs(denom) < 1e-8) {
            if (off < 0) /* outside this plane all along */
                return 0;
            continue;
        }
        const double t = off / denom;
        if (denom < 0)
            lo = t > lo ? t : lo;
        else
            hi = t < hi ? t : hi;
    }
    if (!(hi > lo))
        return 0;
    *t0 = lo;
    *t1 = hi;
    return 1;
}

uint32_t rt_world_material(const rt_world *w, const rt_whit *h)
{
    const rt_scene *s = w->s;
    switch (h->kind) {
    case RT_SHAPE_QUAD:
        return s->shapes.quads.items[h->index].material;
    case RT_SHAPE_MOVER:
        return s->shapes.movers.items[h->index].material;
    default:
        return s->spheres[h->index].material;
    }
}

/* The book's sphere (u, v) of unit outward normal n in the object's frame
 * (frame: 0, or 1 + index of s's frames). */
static void sphere_uv(const rt_scene *s, uint32_t frame, rt_vec3 n, double *u, double *v)
{
    if (frame) {
        const rt_frame *f = &s->shapes.frames.items[frame - 1];
        n = rt_v3(rt_v3_dot(f->row[0], n), rt_v3_dot(f->row[1], n), rt_v3_dot(f->row[2], n));
    }
    const double pi = 3.14159265358979323846;
    const double y = n.y < -1 ? -1 : n.y > 1 ? 1 : n.y;
    *u = (atan2(-n.z, n.x) + pi) / (2 * pi);
    *v = acos(-y) / pi;
}

/* rt_world_surface's spheres, out of line so that the quads' part, the
 * common one in book 2's boxes, can be inlined into the path loop. */
static __attribute__((noinline)) void sphere_surface(const rt_world *w, const rt_whit *h, const rt_ray *ray,
                                                     double time, int want_uv, rt_surface *rec, double *u, double *v)
{
    const rt_scene *s = w->s;
    rt_sphere sp;
    if (h->kind == RT_SHAPE_MOVER) {
        const rt_mover *m = &s->shapes.movers.items[h->index];
        sp = (rt_sphere){.center = rt_mover_center(m, time),
                         .radius = m->radius,
                         .material = m->material,
                         .frame = m->frame};
    } else {
        sp = s->spheres[h->index];
    }
    rt_surface_from_sphere(rec, &sp, ray, h->t);
    if (want_uv) /* the outward normal of the solid sphere */
        sphere_uv(s, sp.frame, rt_v3_scale(rt_v3_sub(rec->p, sp.center), 1.0 / fabs(sp.radius)), u, v);
}

void rt_world_surface(const rt_world *w, const rt_whit *h, const rt_ray *ray, double time, int want_uv,
                      rt_surface *rec, double *u, double *v)
{
    *u = *v = 0.0;
    if (h->kind != RT_SHAPE_QUAD) {
        sphere_surface(w, h, ray, time, want_uv, rec, u, v);
        return;
    }
    const quad_x *q = &w->quads[h->index];
    rec->t = h->t;
    rec->p = rt_ray_at(ray, h->t);
    rec->front_face = rt_v3_dot(ray->dir, q->n) < 0.0;
    rec->normal = rec->front_face ? q->n : rt_v3_neg(q->n);
    if (want_uv) {
        const rt_vec3 hp = rt_v3_sub(rec->p, q->q);
        *u = rt_v3_dot(hp, q->ea);
        *v = rt_v3_dot(hp, q->eb);
    }
}
