/* bvh.c - the BVH's traversals (its build, a binned-SAH binary tree
 * collapsed into 8-wide nodes with float boxes: bvh_build.c): closest-hit
 * traversal testing a node's child boxes in SIMD (eight
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

/* A leaf's spheres: the child code's start and count. */
static inline const prim *leaf_prims(const rt_bvh *b, int32_t code, uint32_t *count)
{
    uint32_t v = ~(uint32_t)code;
    *count = (v & 15u) + 1;
    return b->prims + (v >> 4);
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
