/* world.c - quads and moving spheres in a binary BVH of their boxes, the
 * media's spans, surface records with (u, v). */
#include "world.h"
#include "core_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sphere.h"
#include "status.h"

#define LEAF_ITEMS 4 /* a node of more items is split even when the heuristic says no */
#define STACK 128

/* A quad with what its test needs: its plane (unit normal n, offset d)
 * and the vectors whose dot products with a point's offset from q give its
 * edge coordinates: with N = u x v and w = N / |N|^2, the book's
 * alpha = w . (p x v) = p . (v x w) and beta = w . (u x p) = p . (w x u). */
typedef struct quad_x {
    rt_vec3 q, n, ea, eb;
    double d;
} quad_x;

typedef struct wnode {
    double lo[3], hi[3];
    uint32_t first, count; /* leaf: items [first, first + count); inner: count 0, children first, first + 1 */
} wnode;

struct rt_world {
    const rt_scene *s;
    quad_x *quads;
    quad_x *hull; /* the media's boundary quads, prepared once */
    uint32_t nq, nitems; /* items: quads 0..nq-1, then the moving spheres */
    uint32_t *items;     /* leaf order */
    wnode *nodes;
    uint32_t n_nodes;
    int brute;
    rt_perlin perlin;
};

typedef struct box {
    double lo[3], hi[3];
} box;

static void box_point(box *b, rt_vec3 p, double pad)
{
    const double c[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; k++) {
        b->lo[k] = fmin(b->lo[k], c[k] - pad);
        b->hi[k] = fmax(b->hi[k], c[k] + pad);
    }
}

static box item_box(const rt_world *w, uint32_t i)
{
    box b = {{DBL_MAX, DBL_MAX, DBL_MAX}, {-DBL_MAX, -DBL_MAX, -DBL_MAX}};
    if (i < w->nq) {
        const rt_quad *q = &w->s->shapes.quads.items[i];
        const double pad = 1e-4; /* a flat quad still gets a box with volume (the book's padding) */
        box_point(&b, q->q, pad);
        box_point(&b, rt_v3_add(q->q, q->u), pad);
        box_point(&b, rt_v3_add(q->q, q->v), pad);
        box_point(&b, rt_v3_add(rt_v3_add(q->q, q->u), q->v), pad);
    } else {
        const rt_mover *m = &w->s->shapes.movers.items[i - w->nq];
        box_point(&b, m->center0, fabs(m->radius));
        box_point(&b, m->center1, fabs(m->radius));
    }
    return b;
}

typedef struct keyed {
    double key;
    uint32_t item;
} keyed;

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

/* The surface area heuristic's best split of the sorted items tmp[0, count)
 * (cost in box areas times items, a box test costing one item test), at
 * *at; returns its cost. rest: scratch of count boxes. */
static double best_split(const box *bx, const keyed *tmp, uint32_t count, box *rest, uint32_t *at)
{
    box acc = EMPTY;
    for (uint32_t i = count; i-- > 1;) { /* rest[i]: the box of items i.. */
        grow(&acc, &bx[tmp[i].item]);
        rest[i] = acc;
    }
    acc = EMPTY;
    double best = DBL_MAX;
    for (uint32_t i = 1; i < count; i++) {
        grow(&acc, &bx[tmp[i - 1].item]);
        const double c = area(&acc) * i + area(&rest[i]) * (count - i);
        if (c < best) {
            best = c;
            *at = i;
        }
    }
    return best;
}

/* Node over items [first, first + count): a leaf, or the split the surface
 * area heuristic picks among the orders of the centres on each axis (ties
 * by item, so every rank builds the same tree). An inner node's left child
 * follows it; its `first` is the right child. */
static int build(rt_world *w, const box *bx, keyed *tmp, box *rest, uint32_t first, uint32_t count)
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
        for (uint32_t i = 0; i < count; i++) {
            const uint32_t it = w->items[first + i];
            tmp[i].key = bx[it].lo[k] + bx[it].hi[k];
            tmp[i].item = it;
        }
        qsort(tmp, count, sizeof *tmp, by_key);
        uint32_t a = 0;
        const double c = best_split(bx, tmp, count, rest, &a) + area(&b); /* the two children's boxes tested */
        if (c < best || (count > LEAF_ITEMS && axis < 0)) {
            best = c;
            axis = k;
            at = a;
        }
    }
    if (axis < 0)
        return (int)me;
    for (uint32_t i = 0; i < count; i++) {
        const uint32_t it = w->items[first + i];
        tmp[i].key = bx[it].lo[axis] + bx[it].hi[axis];
        tmp[i].item = it;
    }
    qsort(tmp, count, sizeof *tmp, by_key);
    for (uint32_t i = 0; i < count; i++)
        w->items[first + i] = tmp[i].item;
    build(w, bx, tmp, rest, first, at);
    const int right = build(w, bx, tmp, rest, first + at, count - at);
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

int rt_world_build(rt_world **out, const rt_scene *s, int brute)
{
    *out = NULL;
    rt_world *w = calloc(1, sizeof *w);
    if (!w)
        return RT_ENOMEM;
    w->s = s;
    w->brute = brute;
    w->nq = s->shapes.quads.n;
    w->nitems = w->nq + s->shapes.movers.n;
    rt_perlin_init(&w->perlin, s->tex.noise_seed);
    const size_t n = w->nitems ? w->nitems : 1;
    w->quads = malloc((w->nq ? w->nq : 1) * sizeof *w->quads);
    w->items = malloc(n * sizeof *w->items);
    w->nodes = malloc(2 * n * sizeof *w->nodes);
    box *bx = malloc(n * sizeof *bx);
    keyed *tmp = malloc(n * sizeof *tmp);
    box *rest = malloc(n * sizeof *rest);
    w->hull = malloc((s->media.hull.n ? s->media.hull.n : 1) * sizeof *w->hull);
    int st = (w->quads && w->hull && w->items && w->nodes && bx && tmp && rest) ? RT_OK : RT_ENOMEM;
    for (uint32_t i = 0; i < w->nq && !st; i++)
        w->quads[i] = quad_prep(&s->shapes.quads.items[i]);
    for (uint32_t i = 0; i < s->media.hull.n && !st; i++)
        w->hull[i] = quad_prep(&s->media.hull.items[i]);
    for (uint32_t i = 0; i < w->nitems && !st; i++) {
        w->items[i] = i;
        bx[i] = item_box(w, i);
    }
    if (!st && w->nitems && !brute)
        build(w, bx, tmp, rest, 0, w->nitems);
    free(bx);
    free(tmp);
    free(rest);
    if (st) {
        rt_world_free(w);
        return st;
    }
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
    free(w->nodes);
    free(w);
}

size_t rt_world_bytes(const rt_world *w)
{
    return sizeof *w + ((size_t)w->nq + w->s->media.hull.n) * sizeof *w->quads +
           (size_t)w->nitems * (sizeof *w->items + 2 * sizeof(wnode));
}

const rt_perlin *rt_world_perlin(const rt_world *w) { return &w->perlin; }

/* The book's quad test: the plane, then the edge coordinates in [0, 1]. */
static int quad_t(const quad_x *q, const rt_ray *ray, double tmin, double tmax, double *t)
{
    const double denom = rt_v3_dot(q->n, ray->dir);
    if (fabs(denom) < 1e-8)
        return 0;
    const double tt = (q->d - rt_v3_dot(q->n, ray->orig)) / denom;
    if (!(tt > tmin && tt <= tmax))
        return 0;
    const rt_vec3 hp = rt_v3_sub(rt_ray_at(ray, tt), q->q);
    const double a = rt_v3_dot(hp, q->ea), b = rt_v3_dot(hp, q->eb);
    if (!(a >= 0 && a <= 1 && b >= 0 && b <= 1))
        return 0;
    *t = tt;
    return 1;
}

static rt_vec3 mover_center(const rt_mover *m, double time)
{
    return rt_v3_add(m->center0, rt_v3_scale(rt_v3_sub(m->center1, m->center0), time));
}

/* Item i against the ray: replaces (*best_t, *best) when nearer, or as
 * near with a lower item (quads come first). */
static void test_item(const rt_world *w, uint32_t i, const rt_ray *ray, double a, double time, double tmin,
                      double *best_t, uint32_t *best)
{
    double t;
    int hit;
    if (i < w->nq) {
        hit = quad_t(&w->quads[i], ray, tmin, *best_t, &t);
    } else {
        const rt_mover *m = &w->s->shapes.movers.items[i - w->nq];
        hit = rt_sphere_root(mover_center(m, time), m->radius * m->radius, ray, a, tmin, &t) && t <= *best_t;
    }
    if (hit && (t < *best_t || i < *best)) {
        *best_t = t;
        *best = i;
    }
}

/* Whether the ray meets node n's box within [tmin, tmax]; *enter: where.
 * A NaN slab bound (0 x inf, a ray in a face's plane) leaves the bound as
 * it was: the comparisons below are false for it. */
static inline int box_hit(const wnode *n, const rt_vec3 *o, const rt_vec3 *inv, double tmin, double tmax,
                          double *enter)
{
    const double oo[3] = {o->x, o->y, o->z}, id[3] = {inv->x, inv->y, inv->z};
    for (int k = 0; k < 3; k++) {
        const double t0 = (n->lo[k] - oo[k]) * id[k], t1 = (n->hi[k] - oo[k]) * id[k];
        const double near = t0 < t1 ? t0 : t1, far = t0 < t1 ? t1 : t0;
        tmin = near > tmin ? near : tmin;
        tmax = far < tmax ? far : tmax;
    }
    *enter = tmin;
    return tmin <= tmax;
}

int rt_world_closest(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax, rt_whit *hit)
{
    const double a = rt_v3_len2(ray->dir);
    double best_t = tmax;
    uint32_t best = UINT32_MAX;
    if (w->brute || !w->nitems) {
        for (uint32_t i = 0; i < w->nitems; i++)
            test_item(w, i, ray, a, time, tmin, &best_t, &best);
    } else {
        const rt_vec3 inv = rt_v3(1.0 / ray->dir.x, 1.0 / ray->dir.y, 1.0 / ray->dir.z);
        /* Nearer child first, each with where the ray enters its box: a
         * box entered beyond the closest hit so far is skipped when popped
         * (one touched at it may still hold a tie of lower index). */
        uint32_t stack[STACK];
        double enter[STACK];
        int sp = 0;
        double e0;
        if (box_hit(&w->nodes[0], &ray->orig, &inv, tmin, best_t, &e0)) {
            stack[sp] = 0;
            enter[sp++] = e0;
        }
        while (sp > 0) {
            --sp;
            if (enter[sp] > best_t)
                continue;
            const wnode *n = &w->nodes[stack[sp]];
            if (n->count) {
                for (uint32_t k = n->first; k < n->first + n->count; k++)
                    test_item(w, w->items[k], ray, a, time, tmin, &best_t, &best);
                continue;
            }
            const uint32_t l = stack[sp] + 1, r = n->first;
            double el = 0, er = 0;
            const int hl = box_hit(&w->nodes[l], &ray->orig, &inv, tmin, best_t, &el);
            const int hr = box_hit(&w->nodes[r], &ray->orig, &inv, tmin, best_t, &er);
            if (hl && hr && sp + 2 <= STACK) {
                const int lfirst = el <= er;
                stack[sp] = lfirst ? r : l;
                enter[sp++] = lfirst ? er : el;
                stack[sp] = lfirst ? l : r;
                enter[sp++] = lfirst ? el : er;
            } else if (hl || hr) {
                stack[sp] = hl ? l : r;
                enter[sp++] = hl ? el : er;
            }
        }
    }
    if (best == UINT32_MAX)
        return 0;
    hit->t = best_t;
    hit->kind = best < w->nq ? RT_SHAPE_QUAD : RT_SHAPE_MOVER;
    hit->index = best < w->nq ? best : best - w->nq;
    return 1;
}

int rt_world_medium_span(const rt_world *w, uint32_t k, const rt_ray *ray, double *t0, double *t1)
{
    const rt_medium *m = &w->s->media.media.items[k];
    if (m->shape == RT_MEDIUM_SPHERE) {
        const rt_vec3 oc = rt_v3_sub(ray->orig, m->center);
        const double a = rt_v3_len2(ray->dir), hb = rt_v3_dot(oc, ray->dir);
        const double c = rt_v3_dot(oc, oc) - m->radius * m->radius, disc = hb * hb - a * c;
        if (!(disc > 0))
            return 0;
        const double sq = sqrt(disc);
        *t0 = (-hb - sq) / a;
        *t1 = (-hb + sq) / a;
        return 1;
    }
    /* a convex hull: the line enters at its first crossing, leaves at its last */
    double lo = DBL_MAX, hi = -DBL_MAX, t;
    for (uint32_t i = m->first; i < m->first + m->count; i++) {
        if (quad_t(&w->hull[i], ray, -DBL_MAX, DBL_MAX, &t)) { /* the whole line's crossing */
            lo = fmin(lo, t);
            hi = fmax(hi, t);
        }
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

void rt_world_surface(const rt_world *w, const rt_whit *h, const rt_ray *ray, double time, int want_uv,
                      rt_surface *rec, double *u, double *v)
{
    const rt_scene *s = w->s;
    *u = *v = 0.0;
    if (h->kind == RT_SHAPE_QUAD) {
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
        return;
    }
    rt_sphere sp;
    if (h->kind == RT_SHAPE_MOVER) {
        const rt_mover *m = &s->shapes.movers.items[h->index];
        sp = (rt_sphere){.center = mover_center(m, time),
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
