/* fbox.h - the float boxes of the wide BVHs (the spheres' in bvh*.c, the
 * quads' and moving spheres' in world*.c): a box is stored in float rounded
 * outward, a ray's origin and inverse direction in float, and the interval
 * of a box test is a little wider than the double one, so that float
 * rounding never culls a box the exact ray enters. Private to those files. */
#ifndef RT_FBOX_H
#define RT_FBOX_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "bvh.h" /* RT_BVH_HAVE_SSE2, RT_BVH_HAVE_AVX */

#if RT_BVH_HAVE_SSE2
#include <immintrin.h>
#endif

#define FBOX_WIDTH 8 /* children of a node: one AVX register of floats, two SSE2 ones */

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

/* 1 / d in float, never infinite: a zero component gives +-1e30. */
static inline float safe_inv(double d)
{
    float f = (float)d;
    if (fabsf(f) < 1e-30f)
        f = f < 0 ? -1e-30f : 1e-30f;
    return 1.0f / f;
}

/* v - margin and v + margin rounded outward to float. */
static inline float round_down(double v, double margin)
{
    float f = (float)(v - margin);
    return (double)f > v - margin ? nextafterf(f, -INFINITY) : f;
}
static inline float round_up(double v, double margin)
{
    float f = (float)(v + margin);
    return (double)f < v + margin ? nextafterf(f, INFINITY) : f;
}

/* The box test of a node's FBOX_WIDTH children against a ray: rows holds
 * the boxes' bmin rows x, y, z then their bmax rows; r the rows of the
 * planes the ray meets first (r[0..2], by the signs of its direction) and
 * last (r[3..5]). Stores each child's entry distance in tn and returns the
 * bit mask of the children entered within [tmin_f, tfar_f]. The portable,
 * SSE2 and AVX tests do the same float operations in the same order (no
 * fused multiply-add), so they find the same children with the same
 * entry distances. */
static inline __attribute__((always_inline)) int fbox_portable(const float (*rows)[FBOX_WIDTH], const int r[6],
                                                               const float fo[3], const float fi[3], float tmin_f,
                                                               float tfar_f, float tn[FBOX_WIDTH])
{
    int mask = 0;
    for (int k = 0; k < FBOX_WIDTH; k++) {
        float t0 = (rows[r[0]][k] - fo[0]) * fi[0], t1 = (rows[r[1]][k] - fo[1]) * fi[1];
        float t2 = (rows[r[2]][k] - fo[2]) * fi[2];
        float u0 = (rows[r[3]][k] - fo[0]) * fi[0], u1 = (rows[r[4]][k] - fo[1]) * fi[1];
        float u2 = (rows[r[5]][k] - fo[2]) * fi[2];
        float near = t0 > t1 ? t0 : t1, far = u0 < u1 ? u0 : u1;
        near = t2 > near ? t2 : near;
        near = tmin_f > near ? tmin_f : near;
        far = u2 < far ? u2 : far;
        far = tfar_f < far ? tfar_f : far;
        tn[k] = near;
        mask |= (near <= far) << k;
    }
    return mask;
}

#if RT_BVH_HAVE_SSE2
/* The ray's origin o and inverse direction i as broadcast registers. */
typedef struct fbox_ray4 {
    __m128 ox, oy, oz, ix, iy, iz, tmin;
} fbox_ray4;

static inline __attribute__((always_inline)) int fbox_sse(const float (*rows)[FBOX_WIDTH], const int r[6],
                                                          const fbox_ray4 *v, float tfar_f, float tn[FBOX_WIDTH])
{
    int mask = 0;
    for (int h = 0; h < FBOX_WIDTH; h += 4) {
        __m128 tnx = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[r[0]] + h), v->ox), v->ix);
        __m128 tny = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[r[1]] + h), v->oy), v->iy);
        __m128 tnz = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[r[2]] + h), v->oz), v->iz);
        __m128 tfx = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[r[3]] + h), v->ox), v->ix);
        __m128 tfy = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[r[4]] + h), v->oy), v->iy);
        __m128 tfz = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[r[5]] + h), v->oz), v->iz);
        __m128 vn = _mm_max_ps(_mm_max_ps(tnx, tny), _mm_max_ps(tnz, v->tmin));
        __m128 vf = _mm_min_ps(_mm_min_ps(tfx, tfy), _mm_min_ps(tfz, _mm_set1_ps(tfar_f)));
        mask |= _mm_movemask_ps(_mm_cmple_ps(vn, vf)) << h;
        _mm_storeu_ps(tn + h, vn);
    }
    return mask;
}
#endif

#if RT_BVH_HAVE_AVX
typedef struct fbox_ray8 {
    __m256 ox, oy, oz, ix, iy, iz, tmin;
} fbox_ray8;

static inline __attribute__((always_inline, target("avx"))) int fbox_avx(const float (*rows)[FBOX_WIDTH],
                                                                         const int r[6], const fbox_ray8 *v,
                                                                         float tfar_f, float tn[FBOX_WIDTH])
{
    __m256 tnx = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(rows[r[0]]), v->ox), v->ix);
    __m256 tny = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(rows[r[1]]), v->oy), v->iy);
    __m256 tnz = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(rows[r[2]]), v->oz), v->iz);
    __m256 tfx = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(rows[r[3]]), v->ox), v->ix);
    __m256 tfy = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(rows[r[4]]), v->oy), v->iy);
    __m256 tfz = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(rows[r[5]]), v->oz), v->iz);
    __m256 vn = _mm256_max_ps(_mm256_max_ps(tnx, tny), _mm256_max_ps(tnz, v->tmin));
    __m256 vf = _mm256_min_ps(_mm256_min_ps(tfx, tfy), _mm256_min_ps(tfz, _mm256_set1_ps(tfar_f)));
    _mm256_storeu_ps(tn, vn);
    return _mm256_movemask_ps(_mm256_cmp_ps(vn, vf, _CMP_LE_OQ));
}
#endif

/* The same test without choosing the planes by the direction's signs: each
 * axis's two plane distances, ordered by min and max. For a box with
 * bmin <= bmax and a nonzero inverse direction (safe_inv's) the lesser is
 * exactly the near plane's distance of the tests above (float subtraction
 * and multiplication are monotonic), so these find the same children at
 * the same entry distances; a walk saves choosing and keeping the six rows
 * (the world's, world_traverse.h, whose rays are mostly short bounces).
 * Empty slots (bmin +inf, bmax -inf) may read as entered: callers mask
 * them out with the node's slots in use. */
static inline __attribute__((always_inline)) int fbox_mm_portable(const float (*rows)[FBOX_WIDTH], const float fo[3],
                                                                  const float fi[3], float tmin_f, float tfar_f,
                                                                  float tn[FBOX_WIDTH])
{
    int mask = 0;
    for (int k = 0; k < FBOX_WIDTH; k++) {
        float near = tmin_f, far = tfar_f;
        for (int a = 0; a < 3; a++) {
            const float t0 = (rows[a][k] - fo[a]) * fi[a], t1 = (rows[a + 3][k] - fo[a]) * fi[a];
            const float lo = t0 < t1 ? t0 : t1, hi = t0 < t1 ? t1 : t0;
            near = lo > near ? lo : near;
            far = hi < far ? hi : far;
        }
        tn[k] = near;
        mask |= (near <= far) << k;
    }
    return mask;
}

#if RT_BVH_HAVE_SSE2
static inline __attribute__((always_inline)) int fbox_mm_sse(const float (*rows)[FBOX_WIDTH], const fbox_ray4 *v,
                                                             float tfar_f, float tn[FBOX_WIDTH])
{
    int mask = 0;
    for (int h = 0; h < FBOX_WIDTH; h += 4) {
        __m128 ax = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[0] + h), v->ox), v->ix);
        __m128 ay = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[1] + h), v->oy), v->iy);
        __m128 az = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[2] + h), v->oz), v->iz);
        __m128 bx = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[3] + h), v->ox), v->ix);
        __m128 by = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[4] + h), v->oy), v->iy);
        __m128 bz = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows[5] + h), v->oz), v->iz);
        __m128 vn = _mm_max_ps(_mm_max_ps(_mm_min_ps(ax, bx), _mm_min_ps(ay, by)),
                               _mm_max_ps(_mm_min_ps(az, bz), v->tmin));
        __m128 vf = _mm_min_ps(_mm_min_ps(_mm_max_ps(ax, bx), _mm_max_ps(ay, by)),
                               _mm_min_ps(_mm_max_ps(az, bz), _mm_set1_ps(tfar_f)));
        mask |= _mm_movemask_ps(_mm_cmple_ps(vn, vf)) << h;
        _mm_storeu_ps(tn + h, vn);
    }
    return mask;
}
#endif

#if RT_BVH_HAVE_AVX
/* fbox_mm_avx's ray: the origin and the negated inverse direction
 * broadcast. The plane distance (b - o) * i is computed as (o - b) * -i,
 * which is the same number (IEEE subtraction and multiplication are exact
 * under negation; only a zero's sign may differ, and a zero compares and
 * orders as its negation), so the box's row b can be the instruction's
 * memory operand: six loads fewer per node. */
typedef struct fbox_mray8 {
    __m256 ox, oy, oz, nx, ny, nz, tmin;
} fbox_mray8;

/* v from a ray and tmin_f: (float) of the origin and safe_inv of the
 * direction per axis, with the three axes' conversions, safe_inv's clamp
 * and its division done at once (one rounding and one IEEE division per
 * lane, as the scalar code: the same bits). */
static inline __attribute__((always_inline, target("avx"))) void fbox_mray8_set(fbox_mray8 *v, const rt_ray *ray,
                                                                              float tmin_f)
{
    const __m128 fo = _mm256_cvtpd_ps(_mm256_set_pd(0.0, ray->orig.z, ray->orig.y, ray->orig.x));
    const __m128 fd = _mm256_cvtpd_ps(_mm256_set_pd(1.0, ray->dir.z, ray->dir.y, ray->dir.x));
    const __m128 tiny = _mm_cmplt_ps(_mm_andnot_ps(_mm_set1_ps(-0.0f), fd), _mm_set1_ps(1e-30f));
    const __m128 clamp = _mm_blendv_ps(_mm_set1_ps(1e-30f), _mm_set1_ps(-1e-30f), _mm_cmplt_ps(fd, _mm_setzero_ps()));
    const __m128 fi = _mm_div_ps(_mm_set1_ps(1.0f), _mm_blendv_ps(fd, clamp, tiny));
    const __m128 ni = _mm_xor_ps(fi, _mm_set1_ps(-0.0f));
    const __m256 o8 = _mm256_insertf128_ps(_mm256_castps128_ps256(fo), fo, 1);
    const __m256 n8 = _mm256_insertf128_ps(_mm256_castps128_ps256(ni), ni, 1);
    v->ox = _mm256_permute_ps(o8, 0x00);
    v->oy = _mm256_permute_ps(o8, 0x55);
    v->oz = _mm256_permute_ps(o8, 0xaa);
    v->nx = _mm256_permute_ps(n8, 0x00);
    v->ny = _mm256_permute_ps(n8, 0x55);
    v->nz = _mm256_permute_ps(n8, 0xaa);
    v->tmin = _mm256_set1_ps(tmin_f);
}

static inline __attribute__((always_inline, target("avx"))) int fbox_mm_avx(const float (*rows)[FBOX_WIDTH],
                                                                            const fbox_mray8 *v, float tfar_f,
                                                                            float tn[FBOX_WIDTH])
{
    __m256 ax = _mm256_mul_ps(_mm256_sub_ps(v->ox, _mm256_load_ps(rows[0])), v->nx);
    __m256 ay = _mm256_mul_ps(_mm256_sub_ps(v->oy, _mm256_load_ps(rows[1])), v->ny);
    __m256 az = _mm256_mul_ps(_mm256_sub_ps(v->oz, _mm256_load_ps(rows[2])), v->nz);
    __m256 bx = _mm256_mul_ps(_mm256_sub_ps(v->ox, _mm256_load_ps(rows[3])), v->nx);
    __m256 by = _mm256_mul_ps(_mm256_sub_ps(v->oy, _mm256_load_ps(rows[4])), v->ny);
    __m256 bz = _mm256_mul_ps(_mm256_sub_ps(v->oz, _mm256_load_ps(rows[5])), v->nz);
    __m256 vn = _mm256_max_ps(_mm256_max_ps(_mm256_min_ps(ax, bx), _mm256_min_ps(ay, by)),
                              _mm256_max_ps(_mm256_min_ps(az, bz), v->tmin));
    __m256 vf = _mm256_min_ps(_mm256_min_ps(_mm256_max_ps(ax, bx), _mm256_max_ps(ay, by)),
                              _mm256_min_ps(_mm256_max_ps(az, bz), _mm256_set1_ps(tfar_f)));
    _mm256_storeu_ps(tn, vn);
    return _mm256_movemask_ps(_mm256_cmp_ps(vn, vf, _CMP_LE_OQ));
}
#endif

/* The walk's step down a wide node, shared by the sphere tree
 * (bvh_traverse.h) and the world's (world_traverse.h): of the children the
 * box test kept (mask, their entry distances tn), the nearest becomes
 * *code and the others go onto the stack, farthest first, so the stack
 * pops them nearest first. Returns 0 (nothing pushed) when mask is empty. */
static inline __attribute__((always_inline)) int fbox_descend(int mask, const float tn[FBOX_WIDTH],
                                                              const int32_t child[FBOX_WIDTH], int32_t *code,
                                                              int32_t *stack_node, float *stack_t, int *sp)
{
    if (!mask)
        return 0;
    int c0 = __builtin_ctz(mask);
    mask &= mask - 1;
    if (!mask) { /* one child: go straight on */
        *code = child[c0];
        return 1;
    }
    int c1 = __builtin_ctz(mask);
    mask &= mask - 1;
    if (!mask) { /* two: push the far one */
        int near = tn[c0] <= tn[c1] ? c0 : c1, far = c0 + c1 - near;
        stack_node[*sp] = child[far];
        stack_t[(*sp)++] = tn[far];
        *code = child[near];
        return 1;
    }
    /* more: sorted by entry distance, far first */
    int32_t cc[FBOX_WIDTH];
    float ct[FBOX_WIDTH];
    int m = 0;
    for (int left = mask | (1 << c0) | (1 << c1); left; left &= left - 1) {
        int k = __builtin_ctz(left), j = m++;
        while (j > 0 && ct[j - 1] < tn[k]) {
            ct[j] = ct[j - 1];
            cc[j] = cc[j - 1];
            j--;
        }
        ct[j] = tn[k];
        cc[j] = child[k];
    }
    for (int q = 0; q < m - 1; q++) {
        stack_node[*sp] = cc[q];
        stack_t[(*sp)++] = ct[q];
    }
    *code = cc[m - 1];
    return 1;
}

/* fbox_descend for a walk that wants any hit, not the nearest: the first
 * child kept becomes *code, the others go onto the stack as they come; a
 * child equal to skip is dropped (the world's any-hit walk: the leaf of the
 * shape whose hit it starts from, world_traverse.h). */
static inline __attribute__((always_inline)) int fbox_descend_any(int mask, const float tn[FBOX_WIDTH],
                                                                  const int32_t child[FBOX_WIDTH], int32_t skip,
                                                                  int32_t *code, int32_t *stack_node, float *stack_t,
                                                                  int *sp)
{
    int first = 1;
    for (; mask; mask &= mask - 1) {
        const int k = __builtin_ctz(mask);
        if (child[k] == skip)
            continue;
        if (first) {
            *code = child[k];
            first = 0;
        } else {
            stack_node[*sp] = child[k];
            stack_t[(*sp)++] = tn[k];
        }
    }
    return !first;
}

#endif
