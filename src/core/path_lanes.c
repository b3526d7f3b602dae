/* path_lanes.c - the book-2 path loop eight paths at a time, one in each
 * double lane of an AVX-512 register, for scenes of a few quads (book 2's
 * Cornell box and quads), by brute force or sampling their lights: every
 * quad tested against eight rays at once, the lambertian bounce and its
 * Sobol number in vector code, the lights' estimate at a vertex too (its
 * shadow ray the same quad test), a lane whose path ends given the next
 * sample at once (of its pixel or of the run's next pixels). A path is
 * one chain of dependent work (the division, the hit point, the bounce); eight
 * independent ones side by side turn its latency into throughput
 * (a probe measured the loop first: tools/lockstep_probe.sh at c3bff24).
 *
 * The same bits as path2.c's trace2, lane by lane: each lane does the
 * scalar code's IEEE operations in its order (no fused multiply-add:
 * -ffp-contract=off) in the quad test (world_internal.h's rt_quad_t, the
 * least t and on a tie the lowest quad, as every walk and brute force),
 * the hit point, the normal facing the ray, the bounce (warp.h's
 * rt_warp_lambert_of of sample.h's unit vector: its quarter turns and
 * polynomials) and the throughput; the Sobol numbers are sampler.h's
 * definition, step by step, and so is the lights' estimate (nee8:
 * nee.c's rt_nee_direct and lights.c's sampling); paths start (the
 * camera), end (the sky, emitters weighed by rt_nee_weight, the pixel's
 * sums) and meet the roulette in the scalar code trace2 runs. test
 * e2e_book2 renders such scenes with the tree or brute force (path2.c) and
 * with the lanes: the same image. CPUs without
 * AVX-512 (F and DQ) run trace2. */
#include "path_lanes.h"

#include <string.h>

#include "bvh.h"
#include "nee.h"
#include "path.h"
#include "path2_start.h"
#include "texture.h"
#include "world.h"

/* Quads a scene has at most for the lanes (every one is tested against
 * every ray: past this the tree's walk costs less). */
#define LANES_QUADS 32

#define PI 3.14159265358979323846

/* sobol8's pair: the scattering's, a whole pair of a bounce of an even
 * number of dimensions, without light sampling or with it */
_Static_assert(RT_SAMPLER2_BOUNCE_DIMS % 2 == 0 && RT_SAMPLER2_LIT_BOUNCE_DIMS % 2 == 0 &&
                   RT_SAMPLER2_SCATTER % 2 == 0 && RT_SAMPLER2_LIGHT % 2 == 0 && RT_SAMPLER2_DIM_BOUNCE % 2 == 0,
               "path_lanes.c: the book-2 layout of a bounce's dimensions changed");

int rt_path_lanes_for(const rt_renderer *r)
{
#if RT_BVH_HAVE_AVX
    __builtin_cpu_init();
    if (!__builtin_cpu_supports("avx512f") || !__builtin_cpu_supports("avx512dq"))
        return 0;
    const rt_scene *s = r->scene;
    if (!r->world || r->light_targets || r->job.diffuse != RT_DIFFUSE_LAMBERTIAN ||
        r->job.sampler != RT_SAMPLER_SOBOL || r->lay.ch != 3 || s->media.media.n)
        return 0;
    double rows[13 * LANES_QUADS];
    uint32_t mat[LANES_QUADS];
    const uint32_t n = rt_world_quad_rows(r->world, rows, mat, LANES_QUADS);
    for (uint32_t i = 0; i < n; i++) {
        const rt_material *m = &s->materials[mat[i]];
        if (m->texture || (m->kind != RT_MAT_LAMBERTIAN && m->kind != RT_MAT_EMITTER))
            return 0;
    }
    return n > 0;
#else
    (void)r;
    return 0;
#endif
}

uint32_t rt_path_lanes_run_pixels(uint32_t samples)
{
    /* enough paths that the lanes stay busy to the run's end (a run of 128
     * paths of book 2's Cornell box keeps about 91 % of the lane steps),
     * and no more, so that the farm's master still polls often */
    const uint32_t n = (RT_PATH_LANES_RUN_PATHS + samples - 1) / (samples ? samples : 1);
    return n < 1 ? 1 : n > RT_PATH_LANES_RUN_PIXELS ? RT_PATH_LANES_RUN_PIXELS : n;
}

#if RT_BVH_HAVE_AVX
#include <immintrin.h>

#ifdef __clang__
#pragma clang attribute push(__attribute__((target("avx512f,avx512dq"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx512f,avx512dq")
#endif

#include "lanes_math.h"

/* The run's quads (rt_world_quad_rows) and what their hits do. */
typedef struct quads {
    _Alignas(64) double row[13][LANES_QUADS];
    double col[3][LANES_QUADS]; /* albedo, or emission */
    double emitter[LANES_QUADS], two_sided[LANES_QUADS];
    uint32_t mat[LANES_QUADS];
    uint32_t n;
} quads;

/* The eight lanes: each one's ray, throughput, depth, and its sample's
 * sampler key and bit-reversed index (the Sobol numbers' inputs). */
typedef struct lanes {
    _Alignas(64) double o[3][8];
    double d[3][8], thr[3][8];
    int64_t depth[8], key[8], rev[8];
} lanes;

/* What the lanes keep for light sampling (apart, so that the brute-force
 * loop carries none of it): each lane's path time, the density of its
 * ray's direction (pdf: 0 for a camera ray) and its last step's hit: t,
 * point, normal facing the ray and the throughput that reached it (thr0). */
typedef struct lit8 {
    _Alignas(64) double pdf[8];
    double t[8], hp[3][8], hn[3][8], thr0[3][8], time[8];
} lit8;

/* Each lane's path as the scalar code sees it (its light so far in p.col). */
typedef struct lane {
    path p;
    int64_t *px; /* its pixel's sums */
} lane;

/* Nearest quad of eight rays in (T_MIN, inf): rt_quad_t's operations per
 * lane, the least t and on a tie the lowest quad; *id -1 for none. */
static inline __attribute__((always_inline)) __m512d closest8(const quads *Q, const __m512d o[3], const __m512d d[3],
                                                              __m512i *id)
{
    __m512d best = B(INFINITY);
    __m512i near = I(-1);
    for (uint32_t q = 0; q < Q->n; q++) {
        const __m512d nx = B(Q->row[3][q]), ny = B(Q->row[4][q]), nz = B(Q->row[5][q]);
        const __m512d den = ADD(ADD(MUL(nx, d[0]), MUL(ny, d[1])), MUL(nz, d[2]));
        const __m512d no = ADD(ADD(MUL(nx, o[0]), MUL(ny, o[1])), MUL(nz, o[2]));
        const __m512d t = _mm512_div_pd(SUB(B(Q->row[12][q]), no), den);
        const __m512d hx = SUB(ADD(o[0], MUL(d[0], t)), B(Q->row[0][q]));
        const __m512d hy = SUB(ADD(o[1], MUL(d[1], t)), B(Q->row[1][q]));
        const __m512d hz = SUB(ADD(o[2], MUL(d[2], t)), B(Q->row[2][q]));
        const __m512d a = ADD(ADD(MUL(hx, B(Q->row[6][q])), MUL(hy, B(Q->row[7][q]))), MUL(hz, B(Q->row[8][q])));
        const __m512d b = ADD(ADD(MUL(hx, B(Q->row[9][q])), MUL(hy, B(Q->row[10][q]))), MUL(hz, B(Q->row[11][q])));
        /* a and b in [0, 1], t - T_MIN and |den| - 1e-8 at least 0, in one
         * min (each difference is >= 0 exactly when its compare holds). A
         * NaN operand makes min return its other one, so the NaNs are ruled
         * out apart: t's by the compare t > T_MIN, a's and b's (a hit point
         * that overflowed, where the scalar test's compares all fail) by
         * one compare of the two. Infinite a or b make the min -inf. */
        const __m512d in = _mm512_min_pd(_mm512_min_pd(a, b), _mm512_min_pd(SUB(B(1), a), SUB(B(1), b)));
        const __m512d ok = _mm512_min_pd(_mm512_min_pd(in, SUB(t, B(T_MIN))), SUB(_mm512_abs_pd(den), B(1e-8)));
        const __mmask8 sane = _mm512_cmp_pd_mask(t, B(T_MIN), _CMP_GT_OQ) & _mm512_cmp_pd_mask(a, b, _CMP_ORD_Q);
        const __mmask8 m = _mm512_mask_cmp_pd_mask(sane, ok, _mm512_setzero_pd(), _CMP_GE_OQ);
        const __m512d tm = _mm512_mask_mov_pd(B(INFINITY), m, t);
        near = _mm512_mask_mov_epi64(near, _mm512_cmp_pd_mask(tm, best, _CMP_LT_OQ), I(q));
        best = _mm512_min_pd(tm, best);
    }
    *id = near;
    return best;
}

/* One step of every live lane: its segment's hit, and where it scatters
 * on (a lambertian hit, within the depth limit). Returns the lanes that
 * go on; *miss and *emit: those whose path ends at the sky or a light
 * (their hit's quad in id[]), the lambertian ones that do not go on ended
 * by the depth limit. */
static inline __attribute__((always_inline)) __mmask8 step8(const quads *Q, lanes *L, lit8 *V, __mmask8 live,
                                                            uint32_t max_depth, uint32_t stride, int lights,
                                                            __mmask8 *miss, __mmask8 *emit, int64_t id_out[8])
{
    __m512d o[3], d[3], n[3], dn[3];
    for (int k = 0; k < 3; k++) {
        o[k] = LD(L->o[k]);
        d[k] = LD(L->d[k]);
    }
    const __m512i depth = _mm512_load_si512(L->depth);
    /* the bounce's number, ahead of the test */
    const __m512i u = sobol8(depth, _mm512_load_si512(L->key), _mm512_load_si512(L->rev), stride);
    __m512i id;
    const __m512d t = closest8(Q, o, d, &id);
    if (lights) /* for an emitter's weight (end_light) */
        _mm512_store_pd(V->t, t);
    _mm512_store_si512(id_out, id);
    const __mmask8 hit = _mm512_mask_cmp_epi64_mask(live, id, _mm512_setzero_si512(), _MM_CMPINT_NLT);
    const __m512i idc = _mm512_max_epi64(id, _mm512_setzero_si512());
    const __mmask8 light = _mm512_mask_cmp_pd_mask(hit, _mm512_i64gather_pd(idc, Q->emitter, 8), B(0), _CMP_NEQ_OQ);
    *miss = live & (__mmask8)~hit;
    *emit = light;
    /* the hit record: the point, the normal facing the ray */
    for (int k = 0; k < 3; k++)
        n[k] = _mm512_i64gather_pd(idc, Q->row[3 + k], 8);
    const __mmask8 back = _mm512_cmp_pd_mask(ADD(ADD(MUL(d[0], n[0]), MUL(d[1], n[1])), MUL(d[2], n[2])), B(0),
                                             _CMP_NLT_UQ); /* not (dir . n < 0) */
    for (int k = 0; k < 3; k++) {
        n[k] = _mm512_mask_xor_pd(n[k], back, n[k], B(-0.0));
        o[k] = ADD(o[k], MUL(d[k], t));
    }
    lambert8(u, n, dn);
    const __m512i next = _mm512_add_epi64(depth, I(1));
    const __mmask8 bounce = hit & (__mmask8)~light;
    if (lights) { /* the vertex for the lights' estimate, and rt_nee_scatter's cosine density */
        for (int k = 0; k < 3; k++) {
            _mm512_store_pd(V->hp[k], o[k]);
            _mm512_store_pd(V->hn[k], n[k]);
            _mm512_store_pd(V->thr0[k], LD(L->thr[k]));
        }
        const __m512d len = _mm512_sqrt_pd(dot8(dn, dn));
        _mm512_store_pd(V->pdf, _mm512_mask_div_pd(LD(V->pdf), bounce, dot8(dn, n), MUL(len, B(PI))));
    }
    const __mmask8 on = bounce & _mm512_cmp_epi64_mask(next, I(max_depth), _MM_CMPINT_LT);
    for (int k = 0; k < 3; k++) {
        _mm512_store_pd(L->o[k], _mm512_mask_mov_pd(LD(L->o[k]), bounce, o[k]));
        _mm512_store_pd(L->d[k], _mm512_mask_mov_pd(d[k], bounce, dn[k]));
        const __m512d thr = LD(L->thr[k]);
        _mm512_store_pd(L->thr[k], _mm512_mask_mov_pd(thr, bounce, MUL(thr, _mm512_i64gather_pd(idc, Q->col[k], 8))));
    }
    _mm512_store_si512(L->depth, _mm512_mask_mov_epi64(depth, bounce, next));
    return on;
}

/* The light of the path that ends at lane l (trace2's scalar code), added
 * to what it has (col): the sky's or background's through its throughput
 * (miss2), or an emitter's when it faces the ray or is two-sided
 * (surface2: weighed against the lights' estimate by rt_nee_weight when
 * the job samples them, else w = 1); nothing when the depth limit or the
 * roulette ended it. */
static rt_vec3 end_light(const rt_renderer *r, const quads *Q, const lanes *L, const lit8 *V, int l, int how,
                         uint32_t q, rt_vec3 col)
{
    const rt_vec3 thr = rt_v3(L->thr[0][l], L->thr[1][l], L->thr[2][l]);
    const rt_vec3 dir = rt_v3(L->d[0][l], L->d[1][l], L->d[2][l]);
    if (how == 1) /* the background */
        return rt_v3_add(col, rt_v3_mul(thr, rt_path2_background(r->scene, dir)));
    if (how == 2) { /* an emitter */
        const rt_vec3 n = rt_v3(Q->row[3][q], Q->row[4][q], Q->row[5][q]);
        if (rt_v3_dot(dir, n) < 0.0 || Q->two_sided[q] != 0.0) {
            double w = 1.0;
            if (V) { /* the job samples its lights */
                const rt_ray ray = {rt_v3(L->o[0][l], L->o[1][l], L->o[2][l]), dir};
                const rt_whit h = {V->t[l], RT_SHAPE_QUAD, q, Q->mat[q]};
                w = rt_nee_weight(r, &ray, V->pdf[l], &h, V->time[l]);
            }
            return rt_v3_add(col, rt_v3_scale(rt_v3_mul(thr, rt_v3(Q->col[0][q], Q->col[1][q], Q->col[2][q])), w));
        }
    }
    return col;
}

/* The lights' estimate at lane l's lambertian vertex (path2.c's direct2,
 * scalar: rt_nee_direct by the bounce's light dimensions), added to the
 * path's light, its shadow rays to *segs. */
static void direct(const rt_renderer *r, const quads *Q, const lit8 *V, lane *ln, int l, uint32_t q, uint32_t depth,
                   uint32_t stride, uint64_t *segs)
{
    path *p = &ln->p;
    rt_sampler_seek(&p->smp, RT_SAMPLER2_DIM_BOUNCE + stride * depth + RT_SAMPLER2_LIGHT);
    const rt_nee_bsdf b = {.n = rt_v3(V->hn[0][l], V->hn[1][l], V->hn[2][l])};
    const rt_vec3 at = rt_v3(V->hp[0][l], V->hp[1][l], V->hp[2][l]);
    const rt_vec3 weight = rt_v3_mul(rt_v3(V->thr0[0][l], V->thr0[1][l], V->thr0[2][l]),
                                     rt_v3(Q->col[0][q], Q->col[1][q], Q->col[2][q]));
    p->col = rt_v3_add(p->col, rt_nee_direct(r, at, &b, weight, V->time[l], &p->smp, segs));
}

/* rt_nee_direct at the lambertian vertices of the lanes in `lit`, when
 * every light is a quad (rt_lights_quads): rt_lights_sample's choice and
 * point, the shadow-ray roulette, the shadow ray (the light's quad is the
 * nearest of the lanes' quads along it exactly when nothing stands in front
 * of it, by the walks' rule of the least t and then the lowest quad), the
 * emission toward it and the MIS weight, each lane in the scalar code's
 * operations and order; its numbers the bounce's RT_SAMPLER2_LIGHT (the
 * choice) and the pair after it (the point). Returns the lanes that traced
 * a shadow ray; out[] the light each lane adds (0 where none). */
static __attribute__((noinline)) __mmask8 nee8(const rt_renderer *r, const quads *Q, const rt_light_quads *LQ,
                                               uint32_t nl, const lanes *L, const lit8 *V, __mmask8 lit,
                                               const int64_t id[8], uint32_t stride, double out[3][8])
{
    const __m512i depth = _mm512_sub_epi64(_mm512_load_si512(L->depth), I(1)), key = _mm512_load_si512(L->key),
                  rev = _mm512_load_si512(L->rev);
    const __m512i pair = pair8(depth, stride, RT_SAMPLER2_LIGHT);
    const __m512d u = unit8(_mm512_srli_epi64(point8(pair, key, rev), 32));
    const __m512i u2 = point8(_mm512_add_epi64(pair, I(1)), key, rev);
    /* the light u chooses: the first whose cdf passes u (the last if none) */
    const __m512d cdf = _mm512_loadu_pd(LQ->cdf);
    __m512i lo = _mm512_setzero_si512();
    for (uint32_t i = 0; i + 1 < nl; i++)
        lo = _mm512_mask_add_epi64(lo, _mm512_cmp_pd_mask(B(LQ->cdf[i]), u, _CMP_LE_OQ), lo, I(1));
    const __m512i lo1 = _mm512_sub_epi64(lo, I(1));
    const __m512d below = _mm512_mask_permutexvar_pd(_mm512_setzero_pd(),
                                                     _mm512_cmp_epi64_mask(lo, _mm512_setzero_si512(), _MM_CMPINT_GT),
                                                     lo1, cdf);
#define ROW(x) _mm512_permutexvar_pd(lo, _mm512_loadu_pd(x))
    const __m512d prob = ROW(LQ->prob), area = ROW(LQ->area), emit = ROW(LQ->emit);
    const __m512d rr = _mm512_div_pd(SUB(u, below), prob);
    const __m512d rest = _mm512_mask_mov_pd(
        B(0x1.fffffffffffffp-1), _mm512_cmp_pd_mask(rr, B(1.0), _CMP_LT_OQ),
        _mm512_maskz_mov_pd(_mm512_cmp_pd_mask(rr, B(0.0), _CMP_GT_OQ), rr));
    /* its point, the direction toward it and that direction's density */
    const __m512d s = unit8(_mm512_srli_epi64(u2, 32)), t = unit8(_mm512_and_si512(u2, I(0xffffffffULL)));
    __m512d p[3], n[3], ln[3], dir[3], d[3];
    for (int k = 0; k < 3; k++) {
        p[k] = LD(V->hp[k]);
        n[k] = LD(V->hn[k]);
        ln[k] = ROW(LQ->n[k]);
        d[k] = SUB(ADD(ADD(ROW(LQ->a[k]), MUL(ROW(LQ->b[k]), s)), MUL(ROW(LQ->c[k]), t)), p[k]);
    }
    const __m512d len = _mm512_sqrt_pd(dot8(d, d)), facing = dot8(d, ln);
    __mmask8 ok = lit & _mm512_cmp_pd_mask(len, B(0.0), _CMP_GT_OQ) & _mm512_cmp_pd_mask(facing, B(0.0), _CMP_NEQ_UQ) &
                  (__mmask8)~(_mm512_cmp_pd_mask(ROW(LQ->one_sided), B(0.0), _CMP_NEQ_UQ) &
                              _mm512_cmp_pd_mask(facing, B(0.0), _CMP_GT_OQ));
    const __m512d inv = _mm512_div_pd(B(1.0), len);
    for (int k = 0; k < 3; k++)
        dir[k] = MUL(d[k], inv);
    const __m512d c = _mm512_abs_pd(dot8(dir, ln));
    const __mmask8 cpos = _mm512_cmp_pd_mask(c, B(0.0), _CMP_GT_OQ);
    const __m512d pdf = MUL(prob, _mm512_maskz_div_pd(cpos, MUL(len, len), MUL(c, area)));
    /* the lambertian vertex's cosine and density, the shadow-ray roulette */
    const __m512d cosine = dot8(dir, n);
    ok &= _mm512_cmp_pd_mask(cosine, B(0.0), _CMP_GT_OQ);
    const __m512d pdf_bsdf = _mm512_div_pd(cosine, B(PI));
    ok &= _mm512_cmp_pd_mask(pdf_bsdf, B(0.0), _CMP_GT_OQ);
    const __m512i idc = _mm512_max_epi64(_mm512_load_si512(id), _mm512_setzero_si512());
    __m512d w8[3];
    for (int k = 0; k < 3; k++)
        w8[k] = MUL(LD(V->thr0[k]), _mm512_i64gather_pd(idc, Q->col[k], 8));
    const __m512d luma = ADD(ADD(MUL(B(0.2126), w8[0]), MUL(B(0.7152), w8[1])), MUL(B(0.0722), w8[2]));
    const __m512d est = _mm512_div_pd(MUL(MUL(luma, emit), pdf_bsdf), pdf);
    __m512d keep = B(1.0);
    if (r->job.roulette) {
        const __m512d lim = B(RT_NEE_SHADOW_KEEP_SURFACE), k = _mm512_div_pd(est, lim);
        const __mmask8 low = _mm512_cmp_pd_mask(est, lim, _CMP_LT_OQ);
        keep = _mm512_mask_mov_pd(keep, low, _mm512_maskz_mov_pd(_mm512_cmp_pd_mask(rest, k, _CMP_LT_OQ), k));
    }
    ok &= _mm512_cmp_pd_mask(keep, B(0.0), _CMP_NEQ_UQ);
    /* the shadow ray: the light, if it is the nearest quad along it */
    __m512i near;
    const __m512d th = closest8(Q, p, dir, &near);
    const __m512i quad = _mm512_permutexvar_epi64(lo, _mm512_loadu_si512(LQ->quad));
    __mmask8 lights = ok & _mm512_cmp_epi64_mask(near, quad, _MM_CMPINT_EQ);
    __m512d qn[3], le[3];
    for (int k = 0; k < 3; k++)
        qn[k] = _mm512_i64gather_pd(quad, Q->row[3 + k], 8);
    const __mmask8 faces = _mm512_cmp_pd_mask(dot8(dir, qn), B(0.0), _CMP_LT_OQ) |
                           _mm512_cmp_pd_mask(_mm512_i64gather_pd(quad, Q->two_sided, 8), B(0.0), _CMP_NEQ_UQ);
    __mmask8 glow = 0;
    for (int k = 0; k < 3; k++) {
        le[k] = _mm512_maskz_mov_pd(faces, _mm512_i64gather_pd(quad, Q->col[k], 8));
        glow |= _mm512_cmp_pd_mask(le[k], B(0.0), _CMP_NEQ_UQ);
    }
    lights &= glow;
    const __m512d pl = MUL(prob, _mm512_maskz_div_pd(cpos, MUL(th, th), MUL(c, area)));
    lights &= _mm512_cmp_pd_mask(pl, B(0.0), _CMP_GT_OQ);
    const __m512d w = r->job.light == RT_LIGHT_NEE_ONLY
                          ? B(1.0)
                          : _mm512_div_pd(MUL(pl, pl), ADD(MUL(pl, pl), MUL(pdf_bsdf, pdf_bsdf)));
    const __m512d f = _mm512_div_pd(MUL(pdf_bsdf, w), MUL(pl, keep));
    for (int k = 0; k < 3; k++)
        _mm512_store_pd(out[k], _mm512_maskz_mov_pd(lights, MUL(MUL(w8[k], le[k]), f)));
#undef ROW
    return ok;
}

/* The roulette (path.h's path_roulette) of lane l after the bounce at
 * depth: its number the bounce's +4 (where trace2's sampler stands after
 * the scattering's pair). Returns 0 when it ends the path. */
static int roulette(const rt_renderer *r, lanes *L, lane *ln, int l, uint32_t depth, uint32_t stride)
{
    path *p = &ln->p;
    p->thr = rt_v3(L->thr[0][l], L->thr[1][l], L->thr[2][l]);
    rt_sampler_seek(&p->smp, RT_SAMPLER2_DIM_BOUNCE + stride * depth + RT_SAMPLER2_SCATTER + 2);
    if (!path_roulette(r, p, depth))
        return 0;
    L->thr[0][l] = p->thr.x, L->thr[1][l] = p->thr.y, L->thr[2][l] = p->thr.z;
    return 1;
}

/* The run's pixels' samplers, made at each pixel's first path. */
typedef struct run {
    const rt_renderer *r;
    uint32_t x0, w, y0, s0, ns;
    long i0; /* the run's first pixel */
    int64_t *acc;
    uint64_t next, jobs; /* path next of the run's (pixel-major) */
    pixel_ctx pc[RT_PATH_LANES_RUN_PIXELS];
} run;

/* Lane l takes the run's next path, if any: its camera ray (trace2's
 * start). Returns 0 when none is left. */
static int start(run *R, lanes *L, lit8 *V, lane *ln, int l)
{
    if (R->next == R->jobs)
        return 0;
    const uint64_t j = R->next++;
    const long k = (long)(j / R->ns), i = R->i0 + k;
    pixel_ctx *pc = &R->pc[k];
    if (j % R->ns == 0) {
        const uint32_t x = R->x0 + (uint32_t)(i % R->w), y = R->y0 + (uint32_t)(i / R->w);
        *pc = pixel_start(R->r, x, y, pixel_key(R->r, x, y), 0);
    }
    double time;
    rt_path2_start(R->r, pc, R->s0 + (uint32_t)(j % R->ns), &ln->p, &time);
    if (V) {
        V->time[l] = time;
        V->pdf[l] = 0.0; /* a camera ray's: an emitter it finds counts whole (rt_nee_weight) */
    }
    ln->px = R->acc + i * R->r->lay.ch;
    const rt_ray *ray = &ln->p.ray;
    L->o[0][l] = ray->orig.x, L->o[1][l] = ray->orig.y, L->o[2][l] = ray->orig.z;
    L->d[0][l] = ray->dir.x, L->d[1][l] = ray->dir.y, L->d[2][l] = ray->dir.z;
    L->thr[0][l] = L->thr[1][l] = L->thr[2][l] = 1.0;
    L->depth[l] = 0;
    L->key[l] = (int64_t)pc->smp.key;
    L->rev[l] = (int64_t)ln->p.smp.rev_index;
    return 1;
}

/* The quads of r's world (rt_world_quad_rows) and their materials'. */
static void quads_of(const rt_world *w, const rt_scene *s, quads *Q)
{
    uint32_t mat[LANES_QUADS];
    Q->n = rt_world_quad_rows(w, &Q->row[0][0], mat, LANES_QUADS);
    for (uint32_t q = 0; q < Q->n; q++) {
        const rt_material *m = &s->materials[mat[q]];
        const rt_vec3 c = rt_texture_albedo(s, NULL, m, 0, 0, rt_v3(0, 0, 0)); /* albedo or emission */
        Q->col[0][q] = c.x, Q->col[1][q] = c.y, Q->col[2][q] = c.z;
        Q->emitter[q] = m->kind == RT_MAT_EMITTER;
        Q->two_sided[q] = (m->flags & RT_MAT_TWO_SIDED) != 0;
        Q->mat[q] = mat[q];
    }
}

uint32_t rt_path_lanes_closest(const rt_world *w, const rt_scene *s, const rt_ray ray[8], double t[8], int64_t id[8])
{
    quads Q;
    quads_of(w, s, &Q);
    __m512d o[3], d[3];
    double __attribute__((aligned(64))) v[6][8];
    for (int l = 0; l < 8; l++) {
        v[0][l] = ray[l].orig.x, v[1][l] = ray[l].orig.y, v[2][l] = ray[l].orig.z;
        v[3][l] = ray[l].dir.x, v[4][l] = ray[l].dir.y, v[5][l] = ray[l].dir.z;
    }
    for (int k = 0; k < 3; k++) {
        o[k] = LD(v[k]);
        d[k] = LD(v[3 + k]);
    }
    __m512i near;
    _mm512_storeu_pd(t, closest8(&Q, o, d, &near));
    _mm512_storeu_si512(id, near);
    return Q.n;
}

/* A run's paths: lights (1 when the job samples them) and stride are
 * constants in each of lanes_run's two copies, so that the brute-force
 * one carries nothing of the lights' estimate. */
static inline __attribute__((always_inline)) uint64_t lanes_body(run *R, const int lights, const uint32_t stride)
{
    const rt_renderer *r = R->r;
    quads Q;
    quads_of(r->world, r->scene, &Q);
    lanes L;
    lit8 lit, *V = lights ? &lit : NULL;
    memset(&L, 0, sizeof L);
    lane ln[8];
    __mmask8 live = 0;
    for (int l = 0; l < 8; l++)
        if (start(R, &L, V, &ln[l], l))
            live |= (__mmask8)(1u << l);
    uint64_t segs = 0;
    const uint32_t max_depth = r->job.max_depth;
    const int rr = r->job.roulette;
    rt_light_quads LQ;
    const uint32_t nl = lights ? rt_lights_quads(r->lights, &LQ) : 0;
    while (live) {
        segs += (uint64_t)__builtin_popcount(live);
        __mmask8 miss, emit;
        int64_t __attribute__((aligned(64))) id[8];
        __mmask8 on = step8(&Q, &L, V, live, max_depth, stride, lights, &miss, &emit, id);
        if (nl && on) { /* the lights' estimate at the vertices within the depth limit, before their roulette */
            double __attribute__((aligned(64))) add[3][8];
            segs += (uint64_t)__builtin_popcount(nee8(r, &Q, &LQ, nl, &L, V, on, id, stride, add));
            for (__mmask8 m = on; m; m &= (__mmask8)(m - 1)) {
                const int l = __builtin_ctz(m);
                ln[l].p.col = rt_v3_add(ln[l].p.col, rt_v3(add[0][l], add[1][l], add[2][l]));
            }
        } else if (lights) /* more lights, or not all quads: the scalar estimate */
            for (__mmask8 m = on; m; m &= (__mmask8)(m - 1)) {
                const int l = __builtin_ctz(m);
                direct(r, &Q, V, &ln[l], l, (uint32_t)id[l], (uint32_t)L.depth[l] - 1, stride, &segs);
            }
        if (rr) /* the roulette of the lanes that bounced (their depth is the next one's) */
            for (__mmask8 m = on; m; m &= (__mmask8)(m - 1)) {
                const int l = __builtin_ctz(m);
                if (!roulette(r, &L, &ln[l], l, (uint32_t)L.depth[l] - 1, stride))
                    on &= (__mmask8)~(1u << l);
            }
        for (__mmask8 m = live & (__mmask8)~on; m; m &= (__mmask8)(m - 1)) {
            const int l = __builtin_ctz(m);
            const int how = (miss >> l) & 1 ? 1 : (emit >> l) & 1 ? 2 : 0;
            const rt_vec3 c = end_light(r, &Q, &L, V, l, how, (uint32_t)id[l], ln[l].p.col);
            ln[l].px[0] += rt_render_fix(c.x);
            ln[l].px[1] += rt_render_fix(c.y);
            ln[l].px[2] += rt_render_fix(c.z);
            if (!start(R, &L, V, &ln[l], l))
                on &= (__mmask8)~(1u << l);
            else
                on |= (__mmask8)(1u << l);
        }
        live = on;
    }
    return segs;
}

/* The stride of a bounce's dimensions is path2.c's (no media and no
 * glass-sphere targets in the lanes' scenes). */
static __attribute__((noinline)) uint64_t lanes_run_lit(run *R)
{
    return lanes_body(R, 1, RT_SAMPLER2_LIT_BOUNCE_DIMS);
}
static __attribute__((noinline)) uint64_t lanes_run_brute(run *R)
{
    return lanes_body(R, 0, RT_SAMPLER2_BOUNCE_DIMS);
}
static uint64_t lanes_run(run *R) { return R->r->lights ? lanes_run_lit(R) : lanes_run_brute(R); }

#ifdef __clang__
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

uint64_t rt_path_lanes_run(const rt_renderer *r, uint32_t x0, uint32_t w, uint32_t y0, uint32_t s0, uint32_t s1,
                           long i0, long i1, int64_t *acc)
{
    uint64_t segs = 0;
    for (long a = i0; a < i1 && s0 < s1; a += RT_PATH_LANES_RUN_PIXELS) {
        run R;
        R.r = r, R.x0 = x0, R.w = w, R.y0 = y0, R.s0 = s0, R.ns = s1 - s0, R.acc = acc;
        R.i0 = a;
        R.next = 0;
        R.jobs = (uint64_t)((i1 - a < RT_PATH_LANES_RUN_PIXELS ? i1 - a : RT_PATH_LANES_RUN_PIXELS)) * R.ns;
        segs += lanes_run(&R);
    }
    return segs;
}

#else

uint32_t rt_path_lanes_closest(const rt_world *w, const rt_scene *s, const rt_ray ray[8], double t[8], int64_t id[8])
{
    (void)w, (void)s, (void)ray, (void)t, (void)id;
    return 0;
}

uint64_t rt_path_lanes_run(const rt_renderer *r, uint32_t x0, uint32_t w, uint32_t y0, uint32_t s0, uint32_t s1,
                           long i0, long i1, int64_t *acc)
{
    (void)r, (void)x0, (void)w, (void)y0, (void)s0, (void)s1, (void)i0, (void)i1, (void)acc;
    return 0;
}

#endif
