/* bvh.c - binned-SAH binary build, collapsed into 4-wide nodes with float
 * boxes; closest-hit traversal in SIMD over the four child boxes, exact
 * sphere tests in double.
 *
 * The float boxes only decide which spheres get tested; hits are computed by
 * rt_sphere_intersect in double, the same code brute force runs. Boxes are
 * widened by a margin larger than the float rounding of box and ray, so the
 * closest hit equals brute force's (tests/test_accel.c checks this).
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

#if defined(__SSE2__) && !defined(RT_NO_SIMD)
#include <emmintrin.h>
#define RT_BVH_SSE 1
#else
#define RT_BVH_SSE 0
#endif

#ifndef LEAF_MAX
#define LEAF_MAX 8
#endif
#ifndef TRAV_COST
#define TRAV_COST 1.0
#endif
#ifndef BINS
#define BINS 16
#endif
#define STACK_MAX 256
#define OUTSIDE_MAX 4 /* spheres tested before the traversal, at most */

typedef struct node4 {
    float bmin[3][4];
    float bmax[3][4];
    int32_t child[4]; /* >= 0: node index; < 0: ~(start << 4 | (count - 1)) */
    int32_t nchild; /* bit mask of the child slots in use */
    int32_t pad[3];
} node4;

typedef struct prim {
    double c[3];
    double r2;
    uint32_t index;
    uint32_t pad;
} prim;

struct rt_bvh {
    node4 *nodes;
    int n_nodes, cap_nodes;
    prim *prims; /* the tree's spheres, in leaf order */
    uint32_t n_prims;
    int depth, leaves;
    prim outside[OUTSIDE_MAX]; /* spheres left out of the tree */
    int n_outside;
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

/* Takes out of the tree, into o->outside, the spheres whose box has at least
 * the area of the box around all the remaining ones, largest first, as long
 * as one sphere is left for the tree. order[0, n) lists the spheres; the ones
 * kept are moved to its front. Returns how many are kept. */
static uint32_t take_outside(rt_bvh *o, const rt_scene *s, const box *pbox, uint32_t *order, uint32_t n)
{
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
        if (big_area < box_area(&rest))
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
    if (count <= 2)
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
    if (best_axis < 0 || (count <= LEAF_MAX && leaf_cost <= split_cost)) {
        if (count <= LEAF_MAX || best_axis < 0) {
            if (count > LEAF_MAX) { /* all centroids equal: split in the middle */
                uint32_t half = count / 2;
                int l = build_rec(B, start, half, depth + 1);
                int r = build_rec(B, start + half, count - half, depth + 1);
                B->n[id].left = l;
                B->n[id].right = r;
            }
            return id;
        }
    }
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
    uint32_t nl = i - start;
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
        node4 *q = NULL;
        if (posix_memalign((void **)&q, 64, (size_t)nc * sizeof *q) != 0)
            return RT_ENOMEM;
        if (o->nodes)
            memcpy(q, o->nodes, (size_t)o->n_nodes * sizeof *q);
        free(o->nodes);
        o->nodes = q;
        o->cap_nodes = nc;
    }
    int me = o->n_nodes++;
    int kids[4], nk = 0;
    if (B->n[bid].left < 0) { /* a root that is a single leaf */
        kids[nk++] = bid;
    } else {
        kids[nk++] = B->n[bid].left;
        kids[nk++] = B->n[bid].right;
    }
    /* Open the largest internal child until there are four. */
    while (nk < 4) {
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
    node4 tmp;
    memset(&tmp, 0, sizeof tmp);
    tmp.nchild = (1 << nk) - 1;
    for (int k = 0; k < 4; k++) {
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
    return sizeof *b + (size_t)b->cap_nodes * sizeof(node4) + (size_t)b->n_prims * sizeof(prim);
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
    for (uint32_t i = 0; i < count; i++) {
        double t;
        if (rt_sphere_intersect(rt_v3(p[i].c[0], p[i].c[1], p[i].c[2]), p[i].r2, ray, a, tmin, *closest, &t)) {
            *closest = t;
            *best = p[i].index;
            any = 1;
        }
    }
    return any;
}

static inline int leaf_hit(const rt_bvh *b, int32_t code, const rt_ray *ray, double a, double tmin,
                           double *closest, uint32_t *best, rt_bvh_counts *counts)
{
    uint32_t v = ~(uint32_t)code;
    return test_spheres(b->prims + (v >> 4), (v & 15u) + 1, ray, a, tmin, closest, best, counts);
}

static inline float safe_inv(double d)
{
    float f = (float)d;
    if (fabsf(f) < 1e-30f)
        f = f < 0 ? -1e-30f : 1e-30f;
    return 1.0f / f;
}

/* Ordered depth-first traversal: the nearest hit child is visited next
 * without touching the stack, the others are pushed far to near with their
 * entry distance, and popped entries beyond the current closest hit are
 * dropped. Boxes are tested against the planes a ray meets first and last
 * (chosen once per ray by the direction's signs), so no min/max swap is
 * needed per box. */
static inline __attribute__((always_inline)) int closest(const rt_bvh *b, const rt_ray *ray, double tmin,
                                                          double tmax, rt_hit *hit, const int simd,
                                                          rt_bvh_counts *counts)
{
    if (!b->n_nodes) /* an empty scene: the tree keeps one sphere at least */
        return 0;
    const double a = rt_v3_len2(ray->dir);
    double closest = tmax;
    uint32_t best = UINT32_MAX;
    const float fo[3] = {(float)ray->orig.x, (float)ray->orig.y, (float)ray->orig.z};
    const float fi[3] = {safe_inv(ray->dir.x), safe_inv(ray->dir.y), safe_inv(ray->dir.z)};
    /* Row of the near plane per axis in node4.bmin/bmax, seen as float[6][4]. */
    const int nx = fi[0] < 0 ? 3 : 0, ny = fi[1] < 0 ? 4 : 1, nz = fi[2] < 0 ? 5 : 2;
    const int fx = nx < 3 ? 3 : 0, fy = ny < 3 ? 4 : 1, fz = nz < 3 ? 5 : 2;
    const float tmin_f = (float)tmin * 0.999f;
#if RT_BVH_SSE
    const __m128 ox = _mm_set1_ps(fo[0]), oy = _mm_set1_ps(fo[1]), oz = _mm_set1_ps(fo[2]);
    const __m128 ix = _mm_set1_ps(fi[0]), iy = _mm_set1_ps(fi[1]), iz = _mm_set1_ps(fi[2]);
    const __m128 vtmin = _mm_set1_ps(tmin_f);
#else
    (void)simd;
#endif
    /* The spheres outside the tree first: a hit on one bounds the traversal. */
    test_spheres(b->outside, (uint32_t)b->n_outside, ray, a, tmin, &closest, &best, counts);
    float tfar_f = closest == INFINITY ? INFINITY : (float)closest * 1.0001f;
    int32_t stack_node[STACK_MAX];
    float stack_t[STACK_MAX];
    int sp = 0;
    int32_t code = 0;
    for (;;) {
        if (code < 0) {
            if (leaf_hit(b, code, ray, a, tmin, &closest, &best, counts))
                tfar_f = (float)closest * 1.0001f;
        } else {
            const node4 *n = &b->nodes[code];
            if (counts)
                counts->nodes++;
            const float(*rows)[4] = (const float(*)[4])n->bmin; /* bmin then bmax: 6 rows */
            float tn[4];
            int mask;
#if RT_BVH_SSE
            if (simd) {
                __m128 tnx = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[nx]), ox), ix);
                __m128 tny = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[ny]), oy), iy);
                __m128 tnz = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[nz]), oz), iz);
                __m128 tfx = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[fx]), ox), ix);
                __m128 tfy = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[fy]), oy), iy);
                __m128 tfz = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[fz]), oz), iz);
                __m128 vn = _mm_max_ps(_mm_max_ps(tnx, tny), _mm_max_ps(tnz, vtmin));
                __m128 vf = _mm_min_ps(_mm_min_ps(tfx, tfy), _mm_min_ps(tfz, _mm_set1_ps(tfar_f)));
                mask = _mm_movemask_ps(_mm_cmple_ps(vn, vf)) & n->nchild;
                _mm_storeu_ps(tn, vn);
            } else
#endif
            {
                mask = 0;
                for (int k = 0; k < 4; k++) {
                    float t0 = (rows[nx][k] - fo[0]) * fi[0], t1 = (rows[ny][k] - fo[1]) * fi[1];
                    float t2 = (rows[nz][k] - fo[2]) * fi[2];
                    float u0 = (rows[fx][k] - fo[0]) * fi[0], u1 = (rows[fy][k] - fo[1]) * fi[1];
                    float u2 = (rows[fz][k] - fo[2]) * fi[2];
                    float near = t0 > t1 ? t0 : t1, far = u0 < u1 ? u0 : u1;
                    near = t2 > near ? t2 : near;
                    near = tmin_f > near ? tmin_f : near;
                    far = u2 < far ? u2 : far;
                    far = tfar_f < far ? tfar_f : far;
                    tn[k] = near;
                    mask |= (near <= far) << k;
                }
                mask &= n->nchild;
            }
            if (mask) {
                int c0 = __builtin_ctz(mask);
                mask &= mask - 1;
                if (!mask) { /* one child: go straight on */
                    code = n->child[c0];
                    continue;
                }
                int c1 = __builtin_ctz(mask);
                mask &= mask - 1;
                if (!mask) { /* two: push the far one */
                    int near = tn[c0] <= tn[c1] ? c0 : c1, far = c0 + c1 - near;
                    stack_node[sp] = n->child[far];
                    stack_t[sp++] = tn[far];
                    code = n->child[near];
                    continue;
                }
                /* three or four: sort by entry distance, far first */
                int32_t cc[4];
                float ct[4];
                int m = 0, k = c0;
                for (int left = mask | (1 << c0) | (1 << c1); left; left &= left - 1) {
                    k = __builtin_ctz(left);
                    int j = m++;
                    while (j > 0 && ct[j - 1] < tn[k]) {
                        ct[j] = ct[j - 1];
                        cc[j] = cc[j - 1];
                        j--;
                    }
                    ct[j] = tn[k];
                    cc[j] = n->child[k];
                }
                for (int q = 0; q < m - 1; q++) {
                    stack_node[sp] = cc[q];
                    stack_t[sp++] = ct[q];
                }
                code = cc[m - 1];
                continue;
            }
        }
        /* pop the next entry that can still hold a closer hit */
        for (;;) {
            if (sp == 0)
                goto done;
            sp--;
            if (stack_t[sp] <= tfar_f)
                break;
        }
        code = stack_node[sp];
    }
done:
    if (best == UINT32_MAX)
        return 0;
    hit->t = closest;
    hit->prim = best;
    return 1;
}

int rt_bvh_closest(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit)
{
    return closest(b, ray, tmin, tmax, hit, RT_BVH_SSE, NULL);
}

int rt_bvh_closest_portable(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit)
{
    return closest(b, ray, tmin, tmax, hit, 0, NULL);
}

int rt_bvh_closest_counted(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit,
                           rt_bvh_counts *counts)
{
    return closest(b, ray, tmin, tmax, hit, RT_BVH_SSE, counts);
}
