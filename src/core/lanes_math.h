/* lanes_math.h - the numbers and vectors of path_lanes.c's eight lanes:
 * sampler.h's Sobol points, warp.h's unit fraction and lambertian bounce,
 * vec.h's dot product, each in its scalar definition's operations and
 * order on the eight double (or 64-bit) lanes of an AVX-512 register.
 * Static inline, for path_lanes.c alone, which includes it where its
 * functions are compiled for AVX-512 F and DQ. */
#ifndef RT_LANES_MATH_H
#define RT_LANES_MATH_H

#include <immintrin.h>
#include <stdint.h>

#include "sample.h"
#include "sampler.h"

#define B(x) _mm512_set1_pd(x)
#define I(x) _mm512_set1_epi64((long long)(x))
#define ADD _mm512_add_pd
#define SUB _mm512_sub_pd
#define MUL _mm512_mul_pd
#define LD(p) _mm512_load_pd(p)

/* sampler.h's Sobol 2D number of pair `pair` (above the pixel's pair 0)
 * in each lane (sobol8: its bounce's scattering pair, RT_SAMPLER2_DIM_BOUNCE
 * + stride depth + RT_SAMPLER2_SCATTER over 2): rt_sampler_pair_keys,
 * rt_sampler_nested and rt_sampler_point_of on 64-bit lanes. The 32-bit steps' sums, products
 * and xors keep their low 32 bits in a lane's low half: masked at the end. */
static inline __attribute__((always_inline)) __m512i mix8(__m512i z)
{
    z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 30)), I(RT_RNG_MIX_A));
    z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 27)), I(RT_RNG_MIX_B));
    return _mm512_xor_si512(z, _mm512_srli_epi64(z, 31));
}

static inline __attribute__((always_inline)) __m512i point8(__m512i pair, __m512i key, __m512i rev)
{
    const __m512i lo32 = I(0xffffffffULL);
    const __m512i h =
        mix8(_mm512_xor_si512(key, _mm512_mullo_epi64(_mm512_add_epi64(pair, I(1)), I(RT_SAMPLER_PAIR_STEP))));
    const __m512i seed = _mm512_and_si512(h, lo32);
    const __m512i shift =
        _mm512_or_si512(_mm512_andnot_si512(lo32, h), _mm512_srli_epi64(_mm512_mullo_epi64(h, I(RT_SAMPLER_SHIFT_MUL)), 32));
    __m512i x = _mm512_add_epi64(rev, seed);
    x = _mm512_xor_si512(x, _mm512_mullo_epi64(x, I(RT_SAMPLER_NESTED_A)));
    x = _mm512_mullo_epi64(x, _mm512_or_si512(seed, I(1)));
    x = _mm512_and_si512(_mm512_xor_si512(x, _mm512_mullo_epi64(x, I(RT_SAMPLER_NESTED_B))), lo32);
    __m512i v = x;
    v = _mm512_xor_si512(v, _mm512_and_si512(_mm512_slli_epi64(v, 1), I(0xaaaaaaaau)));
    v = _mm512_xor_si512(v, _mm512_and_si512(_mm512_slli_epi64(v, 2), I(0xccccccccu)));
    v = _mm512_xor_si512(v, _mm512_and_si512(_mm512_slli_epi64(v, 4), I(0xf0f0f0f0u)));
    v = _mm512_xor_si512(v, _mm512_and_si512(_mm512_slli_epi64(v, 8), I(0xff00ff00u)));
    v = _mm512_and_si512(_mm512_xor_si512(v, _mm512_slli_epi64(v, 16)), lo32);
    return _mm512_xor_si512(_mm512_or_si512(_mm512_slli_epi64(x, 32), v), shift);
}

/* The pair of dimension `offset` of each lane's bounce (offset even). */
static inline __attribute__((always_inline)) __m512i pair8(__m512i depth, uint32_t stride, uint32_t offset)
{
    /* depth times 4 or 5 by a shift and an add: a 64-bit product would
     * lengthen each step's chain of dependent work */
    const __m512i d4 = _mm512_slli_epi64(depth, 2);
    const __m512i scaled = stride == 8    ? d4
                           : stride == 10 ? _mm512_add_epi64(d4, depth)
                                          : _mm512_mullo_epi64(depth, I(stride / 2));
    return _mm512_add_epi64(scaled, I((RT_SAMPLER2_DIM_BOUNCE + offset) / 2));
}

static inline __attribute__((always_inline)) __m512i sobol8(__m512i depth, __m512i key, __m512i rev, uint32_t stride)
{
    return point8(pair8(depth, stride, RT_SAMPLER2_SCATTER), key, rev);
}

/* warp.h's rt_warp_unit of each lane's 32 bits. */
static inline __attribute__((always_inline)) __m512d unit8(__m512i v)
{
    return MUL(ADD(_mm512_cvtepu64_pd(v), B(0.5)), B(0x1.0p-32));
}

/* rt_warp_lambert_of(rt_warp_sphere(u), n) in eight lanes: z from u's
 * high 32 bits, the azimuth's quarter turn and its rest from the low 32,
 * the sine and cosine polynomials in sample.h's Horner order; n where n
 * plus the direction is near zero (rt_v3_near_zero). */
static inline __attribute__((always_inline)) void lambert8(__m512i u, const __m512d n[3], __m512d d[3])
{
    const __m512d hi = _mm512_cvtepu64_pd(_mm512_srli_epi64(u, 32));
    const __m512d z = ADD(SUB(MUL(hi, B(0x1.0p-31)), B(1.0)), B(0x1.0p-32));
    const __m512d rho = _mm512_sqrt_pd(MUL(SUB(B(1.0), z), ADD(B(1.0), z)));
    const __m512i q = _mm512_and_si512(u, I(0xffffffffULL));
    const __m512i quarter = _mm512_srli_epi64(_mm512_and_si512(_mm512_add_epi64(q, I(0x20000000)), I(0xffffffffULL)), 30);
    const __m512i rest = _mm512_srai_epi64(_mm512_slli_epi64(_mm512_sub_epi64(q, _mm512_slli_epi64(quarter, 30)), 32), 32);
    const __m512d a = MUL(_mm512_cvtepi64_pd(rest), B(RT_SAMPLE_TURN_RADIANS));
    const __m512d a2 = MUL(a, a);
    static const double ks[6] = RT_SAMPLE_SIN_POLY, kc[7] = RT_SAMPLE_COS_POLY;
    static const double qcos[8] = RT_SAMPLE_QUARTER_COS, qsin[8] = RT_SAMPLE_QUARTER_SIN;
    __m512d ps = B(ks[0]), pc = B(kc[0]);
    for (int i = 1; i < 6; i++)
        ps = ADD(B(ks[i]), MUL(a2, ps));
    for (int i = 1; i < 7; i++)
        pc = ADD(B(kc[i]), MUL(a2, pc));
    const __m512d sa = MUL(a, ps), ca = pc;
    const __m512d qc = _mm512_permutexvar_pd(quarter, _mm512_loadu_pd(qcos));
    const __m512d qs = _mm512_permutexvar_pd(quarter, _mm512_loadu_pd(qsin));
    const __m512d c = SUB(MUL(ca, qc), MUL(sa, qs)), s = ADD(MUL(sa, qc), MUL(ca, qs));
    d[0] = ADD(n[0], MUL(rho, c));
    d[1] = ADD(n[1], MUL(rho, s));
    d[2] = ADD(n[2], z);
    const __m512d e = B(1e-8);
    const __mmask8 zero = _mm512_cmp_pd_mask(_mm512_abs_pd(d[0]), e, _CMP_LT_OQ) &
                          _mm512_cmp_pd_mask(_mm512_abs_pd(d[1]), e, _CMP_LT_OQ) &
                          _mm512_cmp_pd_mask(_mm512_abs_pd(d[2]), e, _CMP_LT_OQ);
    for (int k = 0; k < 3; k++)
        d[k] = _mm512_mask_mov_pd(d[k], zero, n[k]);
}

static inline __attribute__((always_inline)) __m512d dot8(const __m512d a[3], const __m512d b[3])
{
    return ADD(ADD(MUL(a[0], b[0]), MUL(a[1], b[1])), MUL(a[2], b[2]));
}

#endif
