/* bvh_build.c - the BVH's build: binned-SAH binary tree, collapsed into
 * 8-wide nodes with float boxes widened beyond their rounding (see bvh.c for
 * why this gives brute force's hits), the largest spheres kept out of the
 * tree. */
#include "bvh_node.h"
#include "core_internal.h"
#include "fbox.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sphere.h"
#include "status.h"

#if RT_BVH_HAVE_SSE2
#include <immintrin.h>
#endif

/* ---- build ------------------------------------------------------------- */

typedef struct box {
    double lo[3], hi[3];
} box;

typedef struct bnode { /* temporary binary node */
    box b;
    int left, right; /* -1 for leaves */
    uint32_t start, count;
} bnode;

typedef struct builder {
    bnode *n;
    int count, cap;
    box *pbox;
    double (*cent)[3];
    uint32_t *order;
    int err;
} builder;

static void box_empty(box *b)
{
    for (int k = 0; k < 3; k++) {
        b->lo[k] = DBL_MAX;
        b->hi[k] = -DBL_MAX;
    }
}
static void box_grow(box *b, const box *o)
{
    for (int k = 0; k < 3; k++) {
        if (o->lo[k] < b->lo[k])
            b->lo[k] = o->lo[k];
        if (o->hi[k] > b->hi[k])
            b->hi[k] = o->hi[k];
    }
}
static double box_area(const box *b)
{
    double d0 = b->hi[0] - b->lo[0], d1 = b->hi[1] - b->lo[1], d2 = b->hi[2] - b->lo[2];
    if (d0 < 0 || d1 < 0 || d2 < 0)
        return 0.0;
    return 2.0 * (d0 * d1 + d1 * d2 + d2 * d0);
}

static prim prim_of(const rt_scene *s, uint32_t index)
{
    const rt_sphere *sp = &s->spheres[index];
    prim p = {.c = {sp->center.x, sp->center.y, sp->center.z}, .r2 = sp->radius * sp->radius, .index = index};
    return p;
}

static int by_value(const void *pa, const void *pb)
{
    const double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

/* The median of the spheres' radii order[0, n) (n > 0); 0 without memory
 * (then no sphere counts as an outlier). */
static double median_radius(const rt_scene *s, const uint32_t *order, uint32_t n)
{
    double *r = malloc((size_t)n * sizeof *r);
    if (!r)
        return 0.0;
    for (uint32_t i = 0; i < n; i++)
        r[i] = fabs(s->spheres[order[i]].radius);
    qsort(r, n, sizeof *r, by_value);
    double m = r[n / 2];
    free(r);
    return m;
}

/* Takes out of the tree, into o->outside, largest box first and as long as
 * one sphere is left for the tree, the spheres whose box has at least the
 * area of the box around all the remaining ones (a ground), and the
 * outliers: spheres of at least OUTLIER times the median radius. An outlier
 * in the tree makes every box above it as large as its own (tall boxes over
 * a flat field of small spheres, in the final scene), and every ray near
 * them enters those; outside, it costs each ray one sphere test, which does
 * not depend on the traversal's loads and branches (the CPU runs it beside
 * them), and its hit bounds the traversal from the start. order[0, n) lists
 * the spheres; the ones kept are moved to its front. Returns how many are
 * kept. */
#ifndef OUTLIER
#define OUTLIER 4.0
#endif
static uint32_t take_outside(rt_bvh *o, const rt_scene *s, const box *pbox, uint32_t *order, uint32_t n)
{
    const double median = n ? median_radius(s, order, n) : 0.0;
    while (o->n_outside < OUTSIDE_MAX && n > 1) {
        uint32_t big = 0;
        double big_area = box_area(&pbox[order[0]]);
        for (uint32_t i = 1; i < n; i++) {
            double area = box_area(&pbox[order[i]]);
            if (area > big_area) {
                big = i;
                big_area = area;
            }
        }
        box rest;
        box_empty(&rest);
        for (uint32_t i = 0; i < n; i++)
            if (i != big)
                box_grow(&rest, &pbox[order[i]]);
        const int outlier = median > 0.0 && fabs(s->spheres[order[big]].radius) >= OUTLIER * median;
        if (big_area < box_area(&rest) && !outlier)
            break;
        o->outside[o->n_outside++] = prim_of(s, order[big]);
        order[big] = order[--n];
    }
    return n;
}

static int new_bnode(builder *B)
{
    if (B->count == B->cap) {
        int nc = B->cap ? 2 * B->cap : 256;
        bnode *q = realloc(B->n, (size_t)nc * sizeof *q);
        if (!q) {
            B->err = RT_ENOMEM;
            return -1;
        }
        B->n = q;
        B->cap = nc;
    }
    return B->count++;
}

/* Builds the subtree over order[start, start+count); returns its index. */
static int build_rec(builder *B, uint32_t start, uint32_t count, int depth)
{
    int id = new_bnode(B);
    if (id < 0)
        return -1;
    box b, cb;
    box_empty(&b);
    box_empty(&cb);
    for (uint32_t i = start; i < start + count; i++) {
        uint32_t p = B->order[i];
        box_grow(&b, &B->pbox[p]);
        box c = {{B->cent[p][0], B->cent[p][1], B->cent[p][2]}, {B->cent[p][0], B->cent[p][1], B->cent[p][2]}};
        box_grow(&cb, &c);
    }
    B->n[id].b = b;
    B->n[id].left = B->n[id].right = -1;
    B->n[id].start = start;
    B->n[id].count = count;
    if (count <= 1)
        return id;

    /* Binned SAH over the longest-extent axes: try all three. */
    double best_cost = INFINITY;
    int best_axis = -1, best_split = 0;
    for (int axis = 0; axis < 3; axis++) {
        double lo = cb.lo[axis], ext = cb.hi[axis] - cb.lo[axis];
        if (!(ext > 0))
            continue;
        box bb[BINS];
        uint32_t bc[BINS] = {0};
        for (int k = 0; k < BINS; k++)
            box_empty(&bb[k]);
        double scale = BINS / ext;
        for (uint32_t i = start; i < start + count; i++) {
            uint32_t p = B->order[i];
            int k = (int)((B->cent[p][axis] - lo) * scale);
            k = k < 0 ? 0 : k >= BINS ? BINS - 1 : k;
            bc[k]++;
            box_grow(&bb[k], &B->pbox[p]);
        }
        double right_area[BINS];
        uint32_t right_count[BINS];
        box acc;
        box_empty(&acc);
        uint32_t n = 0;
        for (int k = BINS - 1; k > 0; k--) {
            box_grow(&acc, &bb[k]);
            n += bc[k];
            right_area[k] = box_area(&acc);
            right_count[k] = n;
        }
        box_empty(&acc);
        n = 0;
        for (int k = 0; k < BINS - 1; k++) {
            box_grow(&acc, &bb[k]);
            n += bc[k];
            if (n == 0 || right_count[k + 1] == 0)
                continue;
            double cost = box_area(&acc) * n + right_area[k + 1] * right_count[k + 1];
            if (cost < best_cost) {
                best_cost = cost;
                best_axis = axis;
                best_split = k;
            }
        }
    }
    /* Leaf if splitting does not pay (traversal step ~ one sphere test). */
    double leaf_cost = box_area(&b) * count;
    double split_cost = box_area(&b) * TRAV_COST + best_cost;
    if (depth > 48)
        best_axis = -1; /* degenerate input: fall back to median splits */
    if (count <= LEAF_MAX && (best_axis < 0 || leaf_cost <= split_cost))
        return id;
    /* Without an axis to split on (all centroids equal, or too deep), and
     * when a side would be empty: halves. */
    uint32_t nl = 0;
    if (best_axis >= 0) {
        double lo = cb.lo[best_axis], scale = BINS / (cb.hi[best_axis] - cb.lo[best_axis]);
        uint32_t i = start, j = start + count;
        while (i < j) {
            uint32_t p = B->order[i];
            int k = (int)((B->cent[p][best_axis] - lo) * scale);
            k = k < 0 ? 0 : k >= BINS ? BINS - 1 : k;
            if (k <= best_split) {
                i++;
            } else {
                j--;
                B->order[i] = B->order[j];
                B->order[j] = p;
            }
        }
        nl = i - start;
    }
    if (nl == 0 || nl == count)
        nl = count / 2;
    int l = build_rec(B, start, nl, depth + 1);
    int r = build_rec(B, start + nl, count - nl, depth + 1);
    if (l < 0 || r < 0)
        return -1;
    B->n[id].left = l;
    B->n[id].right = r;
    return id;
}

typedef struct collapser {
    rt_bvh *out;
    builder *B;
    double margin_base;
} collapser;

static int emit_leaf(const bnode *n) { return ~(int32_t)((n->start << 4) | (n->count - 1)); }

static int collapse(collapser *C, int bid, int depth)
{
    rt_bvh *o = C->out;
    builder *B = C->B;
    if (depth > o->depth)
        o->depth = depth;
    if (o->n_nodes == o->cap_nodes) {
        int nc = o->cap_nodes ? 2 * o->cap_nodes : 64;
        node *q = NULL;
        if (posix_memalign((void **)&q, 64, (size_t)nc * sizeof *q) != 0)
            return RT_ENOMEM;
        if (o->nodes)
            memcpy(q, o->nodes, (size_t)o->n_nodes * sizeof *q);
        free(o->nodes);
        o->nodes = q;
        o->cap_nodes = nc;
    }
    int me = o->n_nodes++;
    int kids[WIDTH], nk = 0;
    if (B->n[bid].left < 0) { /* a root that is a single leaf */
        kids[nk++] = bid;
    } else {
        kids[nk++] = B->n[bid].left;
        kids[nk++] = B->n[bid].right;
    }
    /* Open the largest internal child until there are WIDTH. */
    while (nk < WIDTH) {
        int best = -1;
        double best_area = -1;
        for (int k = 0; k < nk; k++) {
            const bnode *c = &B->n[kids[k]];
            if (c->left >= 0 && box_area(&c->b) > best_area) {
                best_area = box_area(&c->b);
                best = k;
            }
        }
        if (best < 0)
            break;
        int open = kids[best];
        kids[best] = B->n[open].left;
        kids[nk++] = B->n[open].right;
    }
    node tmp;
    memset(&tmp, 0, sizeof tmp);
    tmp.nchild = (1 << nk) - 1;
    for (int k = 0; k < WIDTH; k++) {
        if (k >= nk) {
            for (int a = 0; a < 3; a++) {
                tmp.bmin[a][k] = INFINITY;
                tmp.bmax[a][k] = -INFINITY;
            }
            tmp.child[k] = 0;
            continue;
        }
        const bnode *c = &B->n[kids[k]];
        for (int a = 0; a < 3; a++) {
            double mag = fmax(fabs(c->b.lo[a]), fabs(c->b.hi[a]));
            double margin = 1e-6 * (1.0 + mag) + C->margin_base;
            tmp.bmin[a][k] = round_down(c->b.lo[a], margin);
            tmp.bmax[a][k] = round_up(c->b.hi[a], margin);
        }
        if (c->left < 0) {
            tmp.child[k] = emit_leaf(c);
            o->leaves++;
        } else {
            int sub = collapse(C, kids[k], depth + 1);
            if (sub < 0)
                return sub;
            tmp.child[k] = sub;
        }
    }
    o->nodes[me] = tmp;
    return me;
}

int rt_bvh_build(rt_bvh **out, const rt_scene *s)
{
    *out = NULL;
    rt_bvh *o = calloc(1, sizeof *o);
    if (!o)
        return RT_ENOMEM;
    uint32_t n = s->n_spheres;
    builder B;
    memset(&B, 0, sizeof B);
    B.pbox = malloc((size_t)(n ? n : 1) * sizeof *B.pbox);
    B.cent = malloc((size_t)(n ? n : 1) * sizeof *B.cent);
    B.order = malloc((size_t)(n ? n : 1) * sizeof *B.order);
    o->prims = malloc((size_t)(n ? n : 1) * sizeof *o->prims);
    int st = (!B.pbox || !B.cent || !B.order || !o->prims) ? RT_ENOMEM : RT_OK;
    double extent = 0.0;
    for (uint32_t i = 0; i < n && !st; i++) {
        const rt_sphere *sp = &s->spheres[i];
        double r = fabs(sp->radius);
        double c[3] = {sp->center.x, sp->center.y, sp->center.z};
        for (int k = 0; k < 3; k++) {
            B.pbox[i].lo[k] = c[k] - r;
            B.pbox[i].hi[k] = c[k] + r;
            B.cent[i][k] = c[k];
            extent = fmax(extent, fabs(c[k]) + r);
        }
        B.order[i] = i;
    }
    if (!st)
        n = take_outside(o, s, B.pbox, B.order, n);
#if RT_BVH_HAVE_AVX
    __builtin_cpu_init();
    o->avx = __builtin_cpu_supports("avx");
#endif
    if (!st && n > 0) {
        int root = build_rec(&B, 0, n, 0);
        st = root < 0 ? (B.err ? B.err : RT_ENOMEM) : B.err;
        if (!st) {
            for (uint32_t i = 0; i < n; i++)
                o->prims[i] = prim_of(s, B.order[i]);
            o->n_prims = n;
            /* Ray origins inside the scene are rounded to float too:
             * widen every box by a little more than that rounding. */
            collapser C = {o, &B, 4.0 * extent * FLT_EPSILON};
            int r = collapse(&C, root, 1);
            if (r < 0)
                st = r;
        }
    }
    free(B.n);
    free(B.pbox);
    free(B.cent);
    free(B.order);
    if (st) {
        rt_bvh_free(o);
        return st;
    }
    *out = o;
    return RT_OK;
}

void rt_bvh_free(rt_bvh *b)
{
    if (!b)
        return;
    free(b->nodes);
    free(b->prims);
    free(b);
}

size_t rt_bvh_bytes(const rt_bvh *b)
{
    return sizeof *b + (size_t)b->cap_nodes * sizeof(node) + (size_t)b->n_prims * sizeof(prim);
}

int rt_bvh_outside(const rt_bvh *b) { return b->n_outside; }

void rt_bvh_stats(const rt_bvh *b, int *nodes, int *leaves, int *depth)
{
    *nodes = b->n_nodes;
    *leaves = b->leaves;
    *depth = b->depth;
}

