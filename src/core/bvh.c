/* bvh.c - binned-SAH binary build, collapsed into 8-wide nodes with float
 * boxes; closest-hit traversal testing a node's child boxes in SIMD (eight
 * at once with AVX, four at a time with SSE2), exact sphere tests in
 * double; and with AVX, a traversal of packets of up to eight rays (one per
 * lane) for rays that travel together, such as a pixel's camera rays.
 *
 * The float boxes only decide which spheres get tested; hits are computed in
 * double with the arithmetic and the closest-hit rule of sphere.h
 * (rt_sphere_closer), which brute force follows too. Boxes are widened by a
 * margin larger than the float rounding of box and ray, so every sphere
 * that could be the closest hit is tested, and as the rule's answer does not
 * depend on the order of the tests, the closest hit equals brute force's,
 * sphere and t, whichever traversal finds it (tests/test_accel.c checks
 * this).
 *
 * A sphere whose box is larger than the box of all the others together (the
 * book's ground, radius 1000) stays out of the tree: nearly every ray would
 * enter its box anyway, so it is tested first, before the traversal, and a
 * ray that hits it starts the traversal with that hit as its bound. */
#include "bvh.h"

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

#define WIDTH 8 /* children per node: one AVX register, two SSE2 ones */

/* Spheres per leaf, at most. One: in an 8-wide tree a leaf takes a child
 * slot, not a node of its own, and one sphere's box is the tightest cull
 * the box test can make. Rays of the final scene tested 2.00 spheres each
 * (the ground included) against 3.04 with leaves of up to two, the earlier
 * rule; whole renders ran 2.4 % faster (scripts/ab_render.sh, paired
 * rounds). A larger value lets the SAH make leaves of up to that many
 * spheres, for experiments. */
#ifndef LEAF_MAX
#define LEAF_MAX 1
#endif
/* A leaf's child code keeps count - 1 in 4 bits (emit_leaf). */
_Static_assert(LEAF_MAX >= 1 && LEAF_MAX <= 16, "LEAF_MAX must be 1 to 16");
#ifndef TRAV_COST
#define TRAV_COST 1.0
#endif
#ifndef BINS
#define BINS 16
#endif
#define OUTSIDE_MAX 4 /* spheres tested before the traversal, at most */

/* Entries the traversal stack can need: each node pushes WIDTH - 1 at most,
 * once per level, and the build keeps the tree shallower than this (splits
 * go to the median past depth 48, so 48 + 32 levels for 2^32 spheres). */
#define STACK_MAX ((WIDTH - 1) * 80)

typedef struct node {
    _Alignas(64) float bmin[3][WIDTH]; /* rows x, y, z of the children's boxes */
    float bmax[3][WIDTH];
    int32_t child[WIDTH]; /* >= 0: node index; < 0: ~(start << 4 | (count - 1)) */
    int32_t nchild;       /* bit mask of the child slots in use */
} node;

typedef struct prim {
    double c[3];
    double r2;
    uint32_t index;
    uint32_t pad;
} prim;

struct rt_bvh {
    node *nodes;
    int n_nodes, cap_nodes;
    prim *prims; /* the tree's spheres, in leaf order */
    uint32_t n_prims;
    int depth, leaves;
    prim outside[OUTSIDE_MAX]; /* spheres left out of the tree */
    int n_outside;
    int avx; /* rt_bvh_closest runs the AVX box test */
};

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
    prim p = {{sp->center.x, sp->center.y, sp->center.z}, sp->radius * sp->radius, index, 0};
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

static float round_down(double v, double margin)
{
    float f = (float)(v - margin);
    return (double)f > v - margin ? nextafterf(f, -INFINITY) : f;
}
static float round_up(double v, double margin)
{
    float f = (float)(v + margin);
    return (double)f < v + margin ? nextafterf(f, INFINITY) : f;
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

/* ---- traversal --------------------------------------------------------- */

/* Tests the spheres p[0, count) in turn, each against the closest hit so
 * far; returns 1 if one of them is closer. Leaves and the spheres outside the
 * tree both go through here. */
static inline int test_spheres(const prim *p, uint32_t count, const rt_ray *ray, double a, double tmin,
                               double *closest, uint32_t *best, rt_bvh_counts *counts)
{
    int any = 0;
    if (counts)
        counts->spheres += count;
    for (uint32_t i = 0; i < count; i++)
        any |= rt_sphere_closer(rt_v3(p[i].c[0], p[i].c[1], p[i].c[2]), p[i].r2, p[i].index, ray, a, tmin, closest,
                                best);
    return any;
}

/* 1 when f's sign bit is set (f < 0 for the nonzero values of safe_inv). */
static inline int sign_bit(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return (int)(u >> 31);
}

/* The float bounds of the box tests around the double interval (tmin,
 * closest): a little wider, so that a box the exact interval enters is never
 * culled by float rounding. INFINITY stays INFINITY. */
#define TMIN_SHRINK 0.999f
#define TFAR_GROW 1.0001f
static inline float near_bound(double tmin) { return (float)tmin * TMIN_SHRINK; }
static inline float far_bound(double closest) { return (float)closest * TFAR_GROW; }

/* A leaf's spheres: the child code's start and count. */
static inline const prim *leaf_prims(const rt_bvh *b, int32_t code, uint32_t *count)
{
    uint32_t v = ~(uint32_t)code;
    *count = (v & 15u) + 1;
    return b->prims + (v >> 4);
}

static inline float safe_inv(double d)
{
    float f = (float)d;
    if (fabsf(f) < 1e-30f)
        f = f < 0 ? -1e-30f : 1e-30f;
    return 1.0f / f;
}

/* The traversal, once per instruction set: bvh_traverse.h holds its body.
 * The baseline copy runs the SSE2 box test (four children at a time) or the
 * portable one; the AVX copy, compiled for AVX and run only where the CPU
 * has it (rt_bvh_build decides), tests eight children at once. All three do
 * the same float operations in the same order (no fused multiply-add), so
 * they find the same children with the same entry distances, visit them in
 * the same order, and the image does not depend on which one a node runs. */
#define TRAVERSE closest_base
#define TRAV_AVX 0
#include "bvh_traverse.h"
#undef TRAVERSE
#undef TRAV_AVX

#if RT_BVH_HAVE_AVX
#ifdef __clang__
#pragma clang attribute push(__attribute__((target("avx"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx")
#endif
#define TRAVERSE closest_avx
#define TRAV_AVX 1
#include "bvh_traverse.h"
#undef TRAVERSE
#undef TRAV_AVX
int rt_bvh_closest_avx(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit)
{
    return closest_avx(b, ray, tmin, tmax, hit, 1, NULL);
}

/* ---- packets of up to eight rays (AVX) ------------------------------------ */

/* Ray data of a packet, one ray per lane: origin, direction, |dir|^2,
 * tmin |dir|^2, and the closest hit so far, its t and its sphere's index (a
 * double, exact for any index; UINT32_MAX for none), as test_spheres keeps
 * them for one ray. */
typedef struct packet {
    double ox[8], oy[8], oz[8], dx[8], dy[8], dz[8], a[8], lo[8];
    double closest[8], best[8];
} packet;

/* All-ones in the lanes of a 4-bit mask. */
static const int64_t lane_bits[16][4] = {
    {0, 0, 0, 0},    {-1, 0, 0, 0},   {0, -1, 0, 0},   {-1, -1, 0, 0},   {0, 0, -1, 0},   {-1, 0, -1, 0},
    {0, -1, -1, 0},  {-1, -1, -1, 0}, {0, 0, 0, -1},   {-1, 0, 0, -1},   {0, -1, 0, -1},  {-1, -1, 0, -1},
    {0, 0, -1, -1},  {-1, 0, -1, -1}, {0, -1, -1, -1}, {-1, -1, -1, -1}};

/* One sphere against the packet's rays in lanes h..h+3 whose bit is set in
 * act: rt_sphere_root's operations per lane, accepted by rt_sphere_closer's
 * rule. */
static inline __attribute__((always_inline)) void sphere_x4(packet *P, int h, const prim *p, int act)
{
    const __m256d cx = _mm256_set1_pd(p->c[0]), cy = _mm256_set1_pd(p->c[1]), cz = _mm256_set1_pd(p->c[2]);
    const __m256d dx = _mm256_load_pd(P->dx + h), dy = _mm256_load_pd(P->dy + h), dz = _mm256_load_pd(P->dz + h);
    __m256d ocx = _mm256_sub_pd(_mm256_load_pd(P->ox + h), cx);
    __m256d ocy = _mm256_sub_pd(_mm256_load_pd(P->oy + h), cy);
    __m256d ocz = _mm256_sub_pd(_mm256_load_pd(P->oz + h), cz);
    __m256d hb = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ocx, dx), _mm256_mul_pd(ocy, dy)), _mm256_mul_pd(ocz, dz));
    __m256d c = _mm256_sub_pd(
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ocx, ocx), _mm256_mul_pd(ocy, ocy)), _mm256_mul_pd(ocz, ocz)),
        _mm256_set1_pd(p->r2));
    __m256d va = _mm256_load_pd(P->a + h);
    __m256d disc = _mm256_sub_pd(_mm256_mul_pd(hb, hb), _mm256_mul_pd(va, c));
    int m = _mm256_movemask_pd(_mm256_cmp_pd(disc, _mm256_setzero_pd(), _CMP_GE_OQ)) & act;
    if (!m)
        return;
    __m256d sq = _mm256_sqrt_pd(_mm256_max_pd(disc, _mm256_setzero_pd()));
    __m256d nb = _mm256_xor_pd(hb, _mm256_set1_pd(-0.0));
    __m256d lo = _mm256_load_pd(P->lo + h), cl = _mm256_load_pd(P->closest + h);
    __m256d n1 = _mm256_sub_pd(nb, sq), n2 = _mm256_add_pd(nb, sq);
    __m256d num = _mm256_blendv_pd(n2, n1, _mm256_cmp_pd(n1, lo, _CMP_GT_OQ));
    m &= _mm256_movemask_pd(_mm256_cmp_pd(num, lo, _CMP_GT_OQ));
    if (!m)
        return;
    __m256d t = _mm256_div_pd(num, va), idx = _mm256_set1_pd((double)p->index), bst = _mm256_load_pd(P->best + h);
    __m256d take = _mm256_or_pd(_mm256_cmp_pd(t, cl, _CMP_LT_OQ),
                                _mm256_and_pd(_mm256_cmp_pd(t, cl, _CMP_EQ_OQ), _mm256_cmp_pd(idx, bst, _CMP_LT_OQ)));
    m &= _mm256_movemask_pd(take);
    if (!m)
        return;
    take = _mm256_castsi256_pd(_mm256_loadu_si256((const __m256i *)lane_bits[m]));
    _mm256_store_pd(P->closest + h, _mm256_blendv_pd(cl, t, take));
    _mm256_store_pd(P->best + h, _mm256_blendv_pd(bst, idx, take));
}

/* The spheres p[0, count) against the packet's rays whose bit is set in act,
 * four lanes at a time. */
static inline __attribute__((always_inline)) void spheres_x8(packet *P, const prim *p, uint32_t count, int act)
{
    for (uint32_t i = 0; i < count; i++) {
        if (act & 15)
            sphere_x4(P, 0, &p[i], act & 15);
        if (act >> 4)
            sphere_x4(P, 4, &p[i], act >> 4);
    }
}

/* far_bound of the eight rays' closest hits so far. */
static inline __attribute__((always_inline)) __m256 packet_tfar(const packet *P)
{
    __m256 f = _mm256_setr_m128(_mm256_cvtpd_ps(_mm256_load_pd(P->closest)),
                                _mm256_cvtpd_ps(_mm256_load_pd(P->closest + 4)));
    return _mm256_mul_ps(f, _mm256_set1_ps(TFAR_GROW));
}

/* The packet traversal: one walk down the tree for all the rays, each node's
 * children tested one at a time against the eight rays (the near and far
 * planes per ray from min and max, as signs may differ between rays). A
 * child goes on with the rays that enter its box (its mask); the nearest
 * child by the entry of its first such ray is visited next, the others are
 * pushed far to near with their mask and the rays' entry distances, and a
 * popped entry keeps only the rays whose entry is not beyond their closest
 * hit by then. Leaves test their spheres against the rays of the mask, in
 * double, with the same rule as one ray's traversal: each ray ends with the
 * hit its own traversal finds, whatever rays share its packet. */
int rt_bvh_closest_packet_avx(const rt_bvh *b, const rt_ray *rays, int n, double tmin, double tmax, rt_hit *hits)
{
    if (n <= 0 || n > 8 || !b->n_nodes)
        return 0;
    _Alignas(32) packet P;
    _Alignas(32) float fo[3][8], fi[3][8];
    for (int k = 0; k < 8; k++) {
        const rt_ray *ray = &rays[k < n ? k : 0];
        P.ox[k] = ray->orig.x;
        P.oy[k] = ray->orig.y;
        P.oz[k] = ray->orig.z;
        P.dx[k] = ray->dir.x;
        P.dy[k] = ray->dir.y;
        P.dz[k] = ray->dir.z;
        P.a[k] = rt_v3_len2(ray->dir);
        P.lo[k] = tmin * P.a[k];
        P.closest[k] = tmax;
        P.best[k] = (double)UINT32_MAX;
        fo[0][k] = (float)ray->orig.x;
        fo[1][k] = (float)ray->orig.y;
        fo[2][k] = (float)ray->orig.z;
        fi[0][k] = safe_inv(ray->dir.x);
        fi[1][k] = safe_inv(ray->dir.y);
        fi[2][k] = safe_inv(ray->dir.z);
    }
    const int all = (1 << n) - 1;
    const __m256 ox = _mm256_load_ps(fo[0]), oy = _mm256_load_ps(fo[1]), oz = _mm256_load_ps(fo[2]);
    const __m256 ix = _mm256_load_ps(fi[0]), iy = _mm256_load_ps(fi[1]), iz = _mm256_load_ps(fi[2]);
    const __m256 vtmin = _mm256_set1_ps(near_bound(tmin));
    spheres_x8(&P, b->outside, (uint32_t)b->n_outside, all);
    __m256 tfar = packet_tfar(&P);
    int32_t stack_node[STACK_MAX];
    int stack_mask[STACK_MAX];
    _Alignas(32) float stack_t[STACK_MAX][8];
    int sp = 0;
    int32_t code = 0;
    int act = all;
    for (;;) {
        if (code < 0) {
            uint32_t count;
            const prim *p = leaf_prims(b, code, &count);
            spheres_x8(&P, p, count, act);
            tfar = packet_tfar(&P);
        } else {
            const node *nd = &b->nodes[code];
            int kid[WIDTH], kmask[WIDTH], nk = 0;
            float key[WIDTH];
            _Alignas(32) float tn[WIDTH][8];
            for (int left = nd->nchild; left; left &= left - 1) {
                int k = __builtin_ctz(left);
                __m256 t0 = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(&nd->bmin[0][k]), ox), ix);
                __m256 t1 = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(&nd->bmax[0][k]), ox), ix);
                __m256 u0 = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(&nd->bmin[1][k]), oy), iy);
                __m256 u1 = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(&nd->bmax[1][k]), oy), iy);
                __m256 w0 = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(&nd->bmin[2][k]), oz), iz);
                __m256 w1 = _mm256_mul_ps(_mm256_sub_ps(_mm256_broadcast_ss(&nd->bmax[2][k]), oz), iz);
                __m256 near = _mm256_max_ps(_mm256_max_ps(_mm256_min_ps(t0, t1), _mm256_min_ps(u0, u1)),
                                            _mm256_max_ps(_mm256_min_ps(w0, w1), vtmin));
                __m256 far = _mm256_min_ps(_mm256_min_ps(_mm256_max_ps(t0, t1), _mm256_max_ps(u0, u1)),
                                           _mm256_min_ps(_mm256_max_ps(w0, w1), tfar));
                int hm = _mm256_movemask_ps(_mm256_cmp_ps(near, far, _CMP_LE_OQ)) & act;
                if (hm) {
                    _mm256_store_ps(tn[nk], near);
                    key[nk] = tn[nk][__builtin_ctz((unsigned)hm)];
                    kid[nk] = nd->child[k];
                    kmask[nk++] = hm;
                }
            }
            if (nk) {
                /* by the entry of each child's first ray, far to near: the
                 * nearest is visited next, the others pushed */
                int order[WIDTH];
                for (int i = 0; i < nk; i++) {
                    int j = i;
                    while (j > 0 && key[order[j - 1]] < key[i]) {
                        order[j] = order[j - 1];
                        j--;
                    }
                    order[j] = i;
                }
                for (int q = 0; q < nk - 1; q++) {
                    int i = order[q];
                    stack_node[sp] = kid[i];
                    stack_mask[sp] = kmask[i];
                    _mm256_store_ps(stack_t[sp++], _mm256_load_ps(tn[i]));
                }
                const int near_i = order[nk - 1];
                code = kid[near_i];
                act = kmask[near_i];
                continue;
            }
        }
        for (;;) {
            if (sp == 0)
                goto done;
            sp--;
            act = stack_mask[sp] & _mm256_movemask_ps(_mm256_cmp_ps(_mm256_load_ps(stack_t[sp]), tfar, _CMP_LE_OQ));
            if (act)
                break;
        }
        code = stack_node[sp];
    }
done:;
    int found = 0;
    for (int k = 0; k < n; k++)
        if (P.best[k] != (double)UINT32_MAX) {
            hits[k].t = P.closest[k];
            hits[k].prim = (uint32_t)P.best[k];
            found |= 1 << k;
        }
    return found;
}
#ifdef __clang__
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif

int rt_bvh_closest_sse(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit)
{
    return closest_base(b, ray, tmin, tmax, hit, RT_BVH_HAVE_SSE2, NULL);
}

int rt_bvh_closest(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit)
{
#if RT_BVH_HAVE_AVX
    if (b->avx)
        return rt_bvh_closest_avx(b, ray, tmin, tmax, hit);
#endif
    return rt_bvh_closest_sse(b, ray, tmin, tmax, hit);
}

int rt_bvh_closest_packet(const rt_bvh *b, const rt_ray *rays, int n, double tmin, double tmax, rt_hit *hits)
{
#if RT_BVH_HAVE_AVX
    if (b->avx)
        return rt_bvh_closest_packet_avx(b, rays, n, tmin, tmax, hits);
#endif
    int found = 0;
    for (int k = 0; k < n; k++)
        found |= rt_bvh_closest(b, &rays[k], tmin, tmax, &hits[k]) << k;
    return found;
}

int rt_bvh_uses_avx(const rt_bvh *b) { return b->avx; }

int rt_bvh_closest_portable(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit)
{
    return closest_base(b, ray, tmin, tmax, hit, 0, NULL);
}

int rt_bvh_closest_counted(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit,
                           rt_bvh_counts *counts)
{
    return closest_base(b, ray, tmin, tmax, hit, RT_BVH_HAVE_SSE2, counts);
}
