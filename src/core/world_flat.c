/* world_flat.c - the world's closest hit in a scene of a few quads (the
 * Cornell boxes of books 2 and 3): every quad tested at once, eight to an
 * AVX-512 register of doubles, instead of the wide tree's walk, on CPUs
 * with AVX-512 (the others walk the tree). No box tests, no stack, no
 * branch per item: in an enclosed room a ray's walk opens several leaves,
 * each a chain of dependent double operations behind a branch, where the
 * flat test runs one or two chains side by side.
 *
 * Where (the rule below): measured on this project's AMD EPYC (Zen 5)
 * host, CPU time of whole renders, least of 11 interleaved runs, `-j 1`,
 * against the tree's AVX walk (docs/PERFORMANCE.md): book3-final lit (12
 * quads and a sphere; 2.19 leaves a ray) 1.07x to 1.08x, brute force
 * 1.06x; cornell-smoke (6 quads, 1.78) 1.03x lit, 1.06x brute force.
 * Not where it does not pay: cornell-box (18 quads in three registers,
 * 2.37) 0.97x to 1.0x; quads (5 quads apart, 0.83: the walk opens about
 * one leaf) 0.93x; simple-light (a quad and 3 spheres, 1.0) 1.0x to
 * 1.05x. AVX2 (four quads a register) was 0.84x on cornell-box.
 *
 * The same bits. Each lane does rt_quad_t's double operations in its
 * order (no fused multiply-add: -ffp-contract=off), so a quad's t and its
 * acceptance are the scalar test's; the hit is the least t, of equal ones
 * the lowest item (rt_world_closest's rule), as brute force's. The spheres
 * and moving spheres after the quads are tested one by one
 * (rt_world_test_item), as brute force does. */
#include "world_internal.h"

#include "status.h"

#include <stdlib.h>
#include <string.h>

/* The scenes the flat test is for (RT_WORLD_BVH): at most this many
 * quads (two registers) and other shapes (tested one by one), in which a
 * ray that enters the scene enters this many of the tree's leaves on
 * average or more (world.c's surface-area estimate: the rooms). */
#define RT_FLAT_QUADS_MAX 16u
#define RT_FLAT_OTHERS_MAX 4u
#define RT_FLAT_LEAVES_MIN 1.5

#if RT_BVH_HAVE_AVX
#include <immintrin.h>

#define FL RT_FLAT_WIDTH

int rt_world_flat_build(rt_world *w, int force, double leaves_per_ray)
{
    __builtin_cpu_init();
    if (!__builtin_cpu_supports("avx512f") || !w->nq ||
        (!force && (w->nq > RT_FLAT_QUADS_MAX || w->nitems - w->nq > RT_FLAT_OTHERS_MAX ||
                    !(leaves_per_ray >= RT_FLAT_LEAVES_MIN))))
        return RT_OK;
    const uint32_t nb = (w->nq + FL - 1) / FL;
    flat8 *f = aligned_alloc(64, nb * sizeof *f); /* nb >= 1: there are quads */
    if (!f)
        return RT_ENOMEM;
    memset(f, 0, nb * sizeof *f);
    for (uint32_t i = 0; i < nb * FL; i++) {
        flat8 *b = &f[i / FL];
        const int l = (int)(i % FL);
        b->item[l] = i;
        if (i >= w->nq)
            continue;
        const quad_x *x = &w->quads[i];
        const rt_vec3 *v[4] = {&x->q, &x->n, &x->ea, &x->eb};
        double(*rows[4])[FL] = {b->q, b->n, b->ea, b->eb};
        for (int k = 0; k < 4; k++) {
            rows[k][0][l] = v[k]->x;
            rows[k][1][l] = v[k]->y;
            rows[k][2][l] = v[k]->z;
        }
        b->d[l] = x->d;
    }
    w->flat = f;
    w->n_flat = nb;
    return RT_OK;
}

#ifdef __clang__
#pragma clang attribute push(__attribute__((target("avx512f"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx512f")
#endif

#define LD(p) _mm512_load_pd(p)
#define MUL _mm512_mul_pd
#define ADD _mm512_add_pd

static inline __attribute__((always_inline)) __m512d dot3(const __m512d a[3], const double (*b)[FL])
{
    return ADD(ADD(MUL(a[0], LD(b[0])), MUL(a[1], LD(b[1]))), MUL(a[2], LD(b[2])));
}

/* The mask of block b's quads the ray hits in (tmin, tmax], their t in *t. */
static inline __attribute__((always_inline)) __mmask8 block_hits(const flat8 *b, const __m512d o[3],
                                                                 const __m512d dir[3], __m512d tmin, __m512d tmax,
                                                                 __m512d *t)
{
    const __m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1.0);
    const __m512d denom = dot3(dir, b->n), no = dot3(o, b->n);
    const __m512d tt = _mm512_div_pd(_mm512_sub_pd(LD(b->d), no), denom);
    __mmask8 ok = _mm512_cmp_pd_mask(_mm512_abs_pd(denom), _mm512_set1_pd(1e-8), _CMP_GE_OQ);
    ok = _mm512_mask_cmp_pd_mask(ok, tt, tmin, _CMP_GT_OQ);
    ok = _mm512_mask_cmp_pd_mask(ok, tt, tmax, _CMP_LE_OQ);
    __m512d h[3];
    for (int k = 0; k < 3; k++)
        h[k] = _mm512_sub_pd(ADD(o[k], MUL(dir[k], tt)), LD(b->q[k]));
    const __m512d a = dot3(h, b->ea), c = dot3(h, b->eb);
    ok = _mm512_mask_cmp_pd_mask(ok, a, zero, _CMP_GE_OQ);
    ok = _mm512_mask_cmp_pd_mask(ok, a, one, _CMP_LE_OQ);
    ok = _mm512_mask_cmp_pd_mask(ok, c, zero, _CMP_GE_OQ);
    ok = _mm512_mask_cmp_pd_mask(ok, c, one, _CMP_LE_OQ);
    *t = tt;
    return ok;
}

static inline __attribute__((always_inline)) void ray_rows(const rt_ray *ray, __m512d o[3], __m512d d[3])
{
    o[0] = _mm512_set1_pd(ray->orig.x);
    o[1] = _mm512_set1_pd(ray->orig.y);
    o[2] = _mm512_set1_pd(ray->orig.z);
    d[0] = _mm512_set1_pd(ray->dir.x);
    d[1] = _mm512_set1_pd(ray->dir.y);
    d[2] = _mm512_set1_pd(ray->dir.z);
}

static int flat_closest(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax, rt_whit *hit)
{
    __m512d o[3], d[3];
    ray_rows(ray, o, d);
    const __m512d vtmin = _mm512_set1_pd(tmin), vtmax = _mm512_set1_pd(tmax);
    __m512d bt = _mm512_set1_pd(INFINITY), bi = _mm512_set1_pd(INFINITY);
    __mmask8 found = 0;
    const flat8 *f = w->flat;
    for (uint32_t k = 0; k < w->n_flat; k++) {
        __m512d tt;
        const __mmask8 ok = block_hits(&f[k], o, d, vtmin, vtmax, &tt);
        /* a lane keeps its earlier (lower) item on a tie */
        const __mmask8 upd = _mm512_mask_cmp_pd_mask(ok, tt, bt, _CMP_LT_OQ);
        bt = _mm512_mask_mov_pd(bt, upd, tt);
        bi = _mm512_mask_mov_pd(bi, upd, LD(f[k].item));
        found |= upd;
    }
    double best_t = tmax;
    uint32_t best = UINT32_MAX;
    if (found) { /* the least t, and the lowest item of the lanes at it */
        best_t = _mm512_mask_reduce_min_pd(found, bt);
        const __mmask8 at = _mm512_mask_cmp_pd_mask(found, bt, _mm512_set1_pd(best_t), _CMP_EQ_OQ);
        best = (uint32_t)_mm512_mask_reduce_min_pd(at, bi);
    }
    for (uint32_t i = w->nq; i < w->nitems; i++)
        rt_world_test_item(w, i, ray, time, tmin, &best_t, &best);
    return rt_world_hit_of(w, best_t, best, hit);
}

static int flat_any(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax, uint32_t item)
{
    __m512d o[3], d[3];
    ray_rows(ray, o, d);
    const __m512d vtmin = _mm512_set1_pd(tmin), vtmax = _mm512_set1_pd(tmax), vitem = _mm512_set1_pd(item);
    const flat8 *f = w->flat;
    for (uint32_t k = 0; k < w->n_flat; k++) {
        __m512d tt;
        const __mmask8 ok = block_hits(&f[k], o, d, vtmin, vtmax, &tt);
        /* in front of the shape, or as near and before it */
        const __mmask8 wins = _mm512_cmp_pd_mask(tt, vtmax, _CMP_LT_OQ) |
                              _mm512_cmp_pd_mask(LD(f[k].item), vitem, _CMP_LT_OQ);
        if (ok & wins)
            return 1;
    }
    double best_t = tmax;
    uint32_t best = item;
    for (uint32_t i = w->nq; i < w->nitems; i++)
        if (i != item && rt_world_test_item(w, i, ray, time, tmin, &best_t, &best))
            return 1;
    return 0;
}

#ifdef __clang__
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

void rt_world_flat_pick(rt_world *w)
{
    w->closest = flat_closest;
    w->occluded = flat_any;
}

#else

int rt_world_flat_build(rt_world *w, int force, double leaves_per_ray)
{
    (void)w;
    (void)force;
    (void)leaves_per_ray;
    return RT_OK;
}
void rt_world_flat_pick(rt_world *w) { (void)w; }

#endif

uint32_t rt_world_quad_rows(const rt_world *w, double *rows, uint32_t *mat, uint32_t max)
{
    if (w->mode != RT_WORLD_BVH || !w->nq || w->nq != w->nitems || w->nq > max)
        return 0;
    for (uint32_t i = 0; i < w->nq; i++) {
        const quad_x *x = &w->quads[i];
        const rt_vec3 v[4] = {x->q, x->n, x->ea, x->eb};
        for (int k = 0; k < 4; k++) {
            rows[(3 * k + 0) * max + i] = v[k].x;
            rows[(3 * k + 1) * max + i] = v[k].y;
            rows[(3 * k + 2) * max + i] = v[k].z;
        }
        rows[12 * max + i] = x->d;
        mat[i] = w->mat[i];
    }
    return w->nq;
}
