/* lockstep_probe.c - a measurement, not part of rt-mpi: how fast could
 * book 2's Cornell box be traced by brute force (issue 35) if eight paths
 * ran in the eight double lanes of an AVX-512 register, in lockstep, each
 * lane taking the next sample as soon as its path ends? Three loops over
 * the same scene (the book's: five walls, the light, two rotated boxes:
 * 18 quads, lambertian, the light two-sided), the same camera and depth:
 *   scalar   one path at a time, every quad tested in turn with the early
 *            exits of rt-mpi's quad test (world_internal.h's rt_quad_t),
 *            the bounce rt-mpi's own (warp.h's rt_warp_lambert);
 *   lanes    eight paths a register, every quad tested against eight rays
 *            at once (the same operations per lane), the lambertian
 *            bounce (warp.h's, its operations per lane) and the refill of
 *            ended lanes in vector code; its numbers from a hash;
 *   sobol    lanes, with each bounce's 2D number from rt-mpi's Sobol
 *            sampler (sampler.h), drawn lane by lane in scalar code.
 * scalar and lanes draw the same numbers and trace the same segments to the
 * bit: built with -DPROBE_CHECK, each prints a fingerprint of every hit (its
 * path, depth and t), and the two agree. Prints nanoseconds a ray segment
 * for each. What it leaves out of a real path loop: rt-mpi's pixel sums,
 * AOVs, statistics, other shapes and materials, light sampling.
 * tools/lockstep_probe.sh builds and runs it beside rt-mpi;
 * docs/notes/experiments.md has the numbers. Build: cc -O2 -march=x86-64-v4 -ffp-contract=off -Isrc/core
 * tools/lockstep_probe.c src/core/sampler.c -lm */
#include <immintrin.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sampler.h"

#define W 200
#define H 200
#define NQ 18
#define TMIN 0.001
#define PI 3.14159265358979323846

/* the quads, struct of arrays: plane (n, d), corner q, edge duals ea, eb
 * (a = (p - q) . ea, b = (p - q) . eb), albedo, emission */
static struct {
    double nx[NQ], ny[NQ], nz[NQ], d[NQ], qx[NQ], qy[NQ], qz[NQ];
    double ax[NQ], ay[NQ], az[NQ], bx[NQ], by[NQ], bz[NQ];
    double r[NQ], g[NQ], b[NQ], em[NQ];
    int n;
} Q;

#define SPP_LOG2 4 /* samples a pixel: a power of two, refill8 divides by a shift */
#define SPP (1 << SPP_LOG2)
#define MAX_DEPTH 40
static int64_t img[W * H * 3]; /* each sample's light in units of 2^-32, so any order sums the same */
static rt_vec3 cam, pix00, du, dv;
static long segments;

static void add_quad(rt_vec3 q, rt_vec3 u, rt_vec3 v, rt_vec3 col, double emit)
{
    const rt_vec3 n = rt_v3_cross(u, v), w = rt_v3_scale(n, 1.0 / rt_v3_dot(n, n));
    const rt_vec3 nn = rt_v3_scale(n, 1.0 / sqrt(rt_v3_dot(n, n)));
    const rt_vec3 ea = rt_v3_cross(v, w), eb = rt_v3_cross(w, u);
    const int i = Q.n++;
    Q.nx[i] = nn.x, Q.ny[i] = nn.y, Q.nz[i] = nn.z, Q.d[i] = rt_v3_dot(nn, q);
    Q.qx[i] = q.x, Q.qy[i] = q.y, Q.qz[i] = q.z;
    Q.ax[i] = ea.x, Q.ay[i] = ea.y, Q.az[i] = ea.z, Q.bx[i] = eb.x, Q.by[i] = eb.y, Q.bz[i] = eb.z;
    Q.r[i] = col.x, Q.g[i] = col.y, Q.b[i] = col.z, Q.em[i] = emit;
}

/* p rotated about y by deg, then moved by t when it is a point */
static rt_vec3 place(rt_vec3 p, double deg, rt_vec3 t, int point)
{
    const double th = deg * PI / 180, c = cos(th), s = sin(th);
    const rt_vec3 r = rt_v3(c * p.x + s * p.z, p.y, -s * p.x + c * p.z);
    return point ? rt_v3_add(r, t) : r;
}

static void add_box(rt_vec3 hi, double deg, rt_vec3 t, rt_vec3 col)
{
    const rt_vec3 dx = rt_v3(hi.x, 0, 0), dy = rt_v3(0, hi.y, 0), dz = rt_v3(0, 0, hi.z);
    const rt_vec3 c[6] = {rt_v3(0, 0, hi.z), rt_v3(hi.x, 0, hi.z), rt_v3(hi.x, 0, 0),
                          rt_v3(0, 0, 0),    rt_v3(0, hi.y, hi.z), rt_v3(0, 0, 0)};
    const rt_vec3 u[6] = {dx, rt_v3_scale(dz, -1), rt_v3_scale(dx, -1), dz, dx, dx};
    const rt_vec3 v[6] = {dy, dy, dy, dy, rt_v3_scale(dz, -1), dz};
    for (int i = 0; i < 6; i++)
        add_quad(place(c[i], deg, t, 1), place(u[i], deg, t, 0), place(v[i], deg, t, 0), col, 0);
}

static void cornell(void)
{
    const rt_vec3 red = rt_v3(.65, .05, .05), white = rt_v3(.73, .73, .73), green = rt_v3(.12, .45, .15);
    add_quad(rt_v3(555, 0, 0), rt_v3(0, 555, 0), rt_v3(0, 0, 555), green, 0);
    add_quad(rt_v3(0, 0, 0), rt_v3(0, 555, 0), rt_v3(0, 0, 555), red, 0);
    add_quad(rt_v3(343, 554, 332), rt_v3(-130, 0, 0), rt_v3(0, 0, -105), rt_v3(0, 0, 0), 15);
    add_quad(rt_v3(0, 0, 0), rt_v3(555, 0, 0), rt_v3(0, 0, 555), white, 0);
    add_quad(rt_v3(555, 555, 555), rt_v3(-555, 0, 0), rt_v3(0, 0, -555), white, 0);
    add_quad(rt_v3(0, 0, 555), rt_v3(555, 0, 0), rt_v3(0, 555, 0), white, 0);
    add_box(rt_v3(165, 330, 165), 15, rt_v3(265, 0, 295), white);
    add_box(rt_v3(165, 165, 165), -18, rt_v3(130, 0, 65), white);
    /* the book's camera: from (278, 278, -800) towards +z, vfov 40, square */
    const double focal = 800, h = 2 * tan(20 * PI / 180) * focal;
    cam = rt_v3(278, 278, -800);
    du = rt_v3(-h / W, 0, 0);
    dv = rt_v3(0, -h / H, 0);
    const rt_vec3 corner = rt_v3_sub(rt_v3_add(cam, rt_v3(0, 0, focal)), rt_v3(-h / 2, -h / 2, 0));
    pix00 = rt_v3_add(corner, rt_v3_scale(rt_v3_add(du, dv), 0.5));
}

static inline uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

static inline uint64_t bounce_bits(uint64_t job, uint64_t depth)
{
    return mix64(job * 0x9e3779b97f4a7c15ULL + depth * 0xd1b54a32d192ed03ULL);
}

/* the camera ray of job j (pixel j / SPP), its jitter from a hash */
static rt_vec3 camera_dir(uint32_t j)
{
    const uint32_t pix = j / SPP, px = pix % W, py = pix / W;
    const uint64_t r = mix64((uint64_t)j * 0x9e3779b97f4a7c15ULL + 12345);
    const double fx = (uint32_t)r * 0x1.0p-32 - 0.5, fy = (uint32_t)(r >> 32) * 0x1.0p-32 - 0.5;
    return rt_v3_sub(rt_v3_add(pix00, rt_v3_add(rt_v3_scale(du, px + fx), rt_v3_scale(dv, py + fy))), cam);
}

/* PROBE_CHECK: an order-free fingerprint of every hit (its path, depth and
 * t's bits), so that scalar and lanes can be shown to trace the same
 * segments to the bit; off for timing */
#ifdef PROBE_CHECK
static uint64_t fingerprint;
#endif

static void add_light(uint32_t job, double r, double g, double b)
{
    int64_t *px = &img[job / SPP * 3];
    px[0] += (int64_t)(r * 0x1.0p32), px[1] += (int64_t)(g * 0x1.0p32), px[2] += (int64_t)(b * 0x1.0p32);
}

/* ---- one path at a time ---------------------------------------------------- */

static int closest_scalar(rt_vec3 o, rt_vec3 d, double *tbest)
{
    double best = INFINITY;
    int id = -1;
    for (int q = 0; q < Q.n; q++) {
        const double den = Q.nx[q] * d.x + Q.ny[q] * d.y + Q.nz[q] * d.z;
        if (fabs(den) < 1e-8)
            continue;
        const double t = (Q.d[q] - (Q.nx[q] * o.x + Q.ny[q] * o.y + Q.nz[q] * o.z)) / den;
        if (!(t > TMIN && t < best))
            continue;
        const double hx = o.x + t * d.x - Q.qx[q], hy = o.y + t * d.y - Q.qy[q], hz = o.z + t * d.z - Q.qz[q];
        const double a = hx * Q.ax[q] + hy * Q.ay[q] + hz * Q.az[q], b = hx * Q.bx[q] + hy * Q.by[q] + hz * Q.bz[q];
        if (a >= 0 && a <= 1 && b >= 0 && b <= 1)
            best = t, id = q;
    }
    *tbest = best;
    return id;
}

static void render_scalar(void)
{
    for (uint32_t j = 0; j < (uint32_t)(W * H * SPP); j++) {
        rt_vec3 o = cam, d = camera_dir(j), thr = rt_v3(1, 1, 1);
        for (int depth = 1;; depth++) {
            segments++;
            double t;
            const int id = closest_scalar(o, d, &t);
            if (id < 0)
                break;
#ifdef PROBE_CHECK
            uint64_t tb;
            memcpy(&tb, &t, 8);
            fingerprint ^= mix64(tb ^ bounce_bits(j, depth - 1));
#endif
            if (Q.em[id] > 0) {
                add_light(j, thr.x * Q.em[id], thr.y * Q.em[id], thr.z * Q.em[id]);
                break;
            }
            if (depth >= MAX_DEPTH)
                break;
            rt_vec3 n = rt_v3(Q.nx[id], Q.ny[id], Q.nz[id]);
            n = rt_v3_dot(n, d) < 0 ? n : rt_v3_scale(n, -1);
            o = rt_v3_add(o, rt_v3_scale(d, t));
            d = rt_warp_lambert(bounce_bits(j, depth), n); /* rt-mpi's lambertian bounce (warp.h) */
            thr = rt_v3(thr.x * Q.r[id], thr.y * Q.g[id], thr.z * Q.b[id]);
        }
    }
}

/* ---- eight paths in lockstep ----------------------------------------------- */

typedef struct {
    __m512d ox, oy, oz, dx, dy, dz, tr, tg, tb;
    __m512i job, depth;
    __m512i key, rev; /* sobol8: each lane's pixel key and bit-reversed sample index */
} lanes;

#define B(x) _mm512_set1_pd(x)
#define I(x) _mm512_set1_epi64((long long)(x))

/* the nearest quad of eight rays: rt_quad_t's operations per lane, the
 * lowest quad on exact ties; every compare folded into one min so that the
 * loop carries only the nearest t */
static inline __m512d closest8(const lanes *L, __m512i *id)
{
    const __m512d ox = L->ox, oy = L->oy, oz = L->oz, dx = L->dx, dy = L->dy, dz = L->dz; /* in registers */
    __m512d best = B(INFINITY);
    __m512i near = _mm512_set1_epi64(-1);
    for (int q = 0; q < Q.n; q++) {
        const __m512d den = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(B(Q.nx[q]), dx), _mm512_mul_pd(B(Q.ny[q]), dy)),
                                          _mm512_mul_pd(B(Q.nz[q]), dz));
        const __m512d no = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(B(Q.nx[q]), ox), _mm512_mul_pd(B(Q.ny[q]), oy)),
                                         _mm512_mul_pd(B(Q.nz[q]), oz));
        const __m512d t = _mm512_div_pd(_mm512_sub_pd(B(Q.d[q]), no), den);
        const __m512d hx = _mm512_sub_pd(_mm512_add_pd(ox, _mm512_mul_pd(t, dx)), B(Q.qx[q]));
        const __m512d hy = _mm512_sub_pd(_mm512_add_pd(oy, _mm512_mul_pd(t, dy)), B(Q.qy[q]));
        const __m512d hz = _mm512_sub_pd(_mm512_add_pd(oz, _mm512_mul_pd(t, dz)), B(Q.qz[q]));
        const __m512d a = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(hx, B(Q.ax[q])), _mm512_mul_pd(hy, B(Q.ay[q]))),
                                        _mm512_mul_pd(hz, B(Q.az[q])));
        const __m512d b = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(hx, B(Q.bx[q])), _mm512_mul_pd(hy, B(Q.by[q]))),
                                        _mm512_mul_pd(hz, B(Q.bz[q])));
        /* a, b in [0, 1], t - TMIN and |den| - 1e-8 in one min (where den
         * is below 1e-8 its own term decides: a NaN a or b makes min return
         * its other operand, never a false pass), t > TMIN apart */
        const __m512d in =
            _mm512_min_pd(_mm512_min_pd(a, b), _mm512_min_pd(_mm512_sub_pd(B(1), a), _mm512_sub_pd(B(1), b)));
        const __m512d ok = _mm512_min_pd(_mm512_min_pd(in, _mm512_sub_pd(t, B(TMIN))),
                                         _mm512_sub_pd(_mm512_abs_pd(den), B(1e-8)));
        const __mmask8 beyond = _mm512_cmp_pd_mask(t, B(TMIN), _CMP_GT_OQ);
        const __mmask8 m = _mm512_mask_cmp_pd_mask(beyond, ok, _mm512_setzero_pd(), _CMP_GE_OQ);
        const __m512d tm = _mm512_mask_mov_pd(B(INFINITY), m, t);
        near = _mm512_mask_mov_epi64(near, _mm512_cmp_pd_mask(tm, best, _CMP_LT_OQ), _mm512_set1_epi64(q));
        best = _mm512_min_pd(tm, best);
    }
    *id = near;
    return best;
}

/* rt_warp_lambert (warp.h, sample.h's rt_sample_unit_vector_bits) in
 * eight lanes, the same operations in the same order: z from the high 32
 * bits, the azimuth's quarter turn and its rest from the low 32, the sine
 * and cosine polynomials in Horner form; n where n plus the direction is
 * near zero. */
static inline void lambert8(__m512i u, __m512d nx, __m512d ny, __m512d nz, __m512d *dx, __m512d *dy, __m512d *dz)
{
    const __m512d hi = _mm512_cvtepu64_pd(_mm512_srli_epi64(u, 32));
    const __m512d z = _mm512_add_pd(_mm512_sub_pd(_mm512_mul_pd(hi, B(0x1.0p-31)), B(1.0)), B(0x1.0p-32));
    const __m512d rho = _mm512_sqrt_pd(_mm512_mul_pd(_mm512_sub_pd(B(1.0), z), _mm512_add_pd(B(1.0), z)));
    const __m512i q = _mm512_and_si512(u, _mm512_set1_epi64(0xffffffff));
    const __m512i quarter = _mm512_srli_epi64(_mm512_and_si512(_mm512_add_epi64(q, _mm512_set1_epi64(0x20000000)),
                                                               _mm512_set1_epi64(0xffffffff)), 30);
    const __m512i off = _mm512_sub_epi64(q, _mm512_slli_epi64(quarter, 30));
    const __m512i rest = _mm512_srai_epi64(_mm512_slli_epi64(off, 32), 32); /* its low 32 bits, signed */
    const __m512d a = _mm512_mul_pd(_mm512_cvtepi64_pd(rest), B(6.28318530717958647692 / 4294967296.0));
    const __m512d a2 = _mm512_mul_pd(a, a);
    static const double ks[] = {-1.0 / 39916800, 1.0 / 362880, -1.0 / 5040, 1.0 / 120, -1.0 / 6, 1.0};
    static const double kc[] = {1.0 / 479001600, -1.0 / 3628800, 1.0 / 40320, -1.0 / 720, 1.0 / 24, -1.0 / 2, 1.0};
    __m512d ps = B(ks[0]), pc = B(kc[0]);
    for (int i = 1; i < 6; i++)
        ps = _mm512_add_pd(B(ks[i]), _mm512_mul_pd(a2, ps));
    for (int i = 1; i < 7; i++)
        pc = _mm512_add_pd(B(kc[i]), _mm512_mul_pd(a2, pc));
    const __m512d sa = _mm512_mul_pd(a, ps), ca = pc;
    const __m512d qcos = _mm512_permutexvar_pd(quarter, _mm512_setr_pd(1, 0, -1, 0, 0, 0, 0, 0));
    const __m512d qsin = _mm512_permutexvar_pd(quarter, _mm512_setr_pd(0, 1, 0, -1, 0, 0, 0, 0));
    const __m512d c = _mm512_sub_pd(_mm512_mul_pd(ca, qcos), _mm512_mul_pd(sa, qsin));
    const __m512d s = _mm512_add_pd(_mm512_mul_pd(sa, qcos), _mm512_mul_pd(ca, qsin));
    *dx = _mm512_add_pd(nx, _mm512_mul_pd(rho, c));
    *dy = _mm512_add_pd(ny, _mm512_mul_pd(rho, s));
    *dz = _mm512_add_pd(nz, z);
    const __m512d e = B(1e-8);
    const __mmask8 zero = _mm512_cmp_pd_mask(_mm512_abs_pd(*dx), e, _CMP_LT_OQ) &
                          _mm512_cmp_pd_mask(_mm512_abs_pd(*dy), e, _CMP_LT_OQ) &
                          _mm512_cmp_pd_mask(_mm512_abs_pd(*dz), e, _CMP_LT_OQ);
    *dx = _mm512_mask_mov_pd(*dx, zero, nx);
    *dy = _mm512_mask_mov_pd(*dy, zero, ny);
    *dz = _mm512_mask_mov_pd(*dz, zero, nz);
}

static inline __m512i mix8(__m512i z)
{
    z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 30)), _mm512_set1_epi64(0xbf58476d1ce4e5b9ULL));
    z = _mm512_mullo_epi64(_mm512_xor_si512(z, _mm512_srli_epi64(z, 27)), _mm512_set1_epi64(0x94d049bb133111ebULL));
    return _mm512_xor_si512(z, _mm512_srli_epi64(z, 31));
}

/* bounce_bits in eight lanes */
static inline __m512i bounce_bits8(__m512i job, __m512i depth)
{
    return mix8(_mm512_add_epi64(_mm512_mullo_epi64(job, I(0x9e3779b97f4a7c15ULL)),
                                 _mm512_mullo_epi64(depth, I(0xd1b54a32d192ed03ULL))));
}

/* the sobol variant's state: each pixel's sampler (made on its first
 * sample), each lane's */
static rt_sampler_pixel *pixels;
static unsigned char *pixel_made;
static rt_sampler lane_smp[8];

static void lane_sampler(int l, uint32_t j)
{
    const uint32_t pix = j / SPP;
    if (!pixel_made[pix]) {
        rt_sampler_for_pixel(&pixels[pix], RT_SAMPLER_SOBOL, mix64(pix + 42u));
        pixel_made[pix] = 1;
    }
    lane_smp[l] = rt_sampler_start(&pixels[pix], j % SPP);
}

/* each continuing lane's bounce number */
/* sampler.h's rt_sampler_get2d at the bounce's scattering pair (4 x
 * depth) in eight lanes, every step of its definition (rt_sampler_pair_keys,
 * rt_sampler_nested, rt_sampler_point_of) on 64-bit lanes: sums, products
 * and xors of the 32-bit steps keep their low 32 bits, masked at the end */
static inline __m512i sobol8(const lanes *L)
{
    const __m512i lo32 = I(0xffffffffULL);
    const __m512i pair = _mm512_slli_epi64(L->depth, 2);
    const __m512i h =
        mix8(_mm512_xor_si512(L->key, _mm512_mullo_epi64(_mm512_add_epi64(pair, I(1)), I(0x9fb21c651e98df25ULL))));
    const __m512i seed = _mm512_and_si512(h, lo32);
    const __m512i shift = _mm512_or_si512(_mm512_andnot_si512(lo32, h),
                                          _mm512_srli_epi64(_mm512_mullo_epi64(h, I(0xd1b54a32d192ed03ULL)), 32));
    __m512i x = _mm512_add_epi64(L->rev, seed);
    x = _mm512_xor_si512(x, _mm512_mullo_epi64(x, I(0x3c6ef372u)));
    x = _mm512_mullo_epi64(x, _mm512_or_si512(seed, I(1)));
    x = _mm512_and_si512(_mm512_xor_si512(x, _mm512_mullo_epi64(x, I(0xa54ff53au))), lo32);
    __m512i v = x;
    v = _mm512_xor_si512(v, _mm512_and_si512(_mm512_slli_epi64(v, 1), I(0xaaaaaaaau)));
    v = _mm512_xor_si512(v, _mm512_and_si512(_mm512_slli_epi64(v, 2), I(0xccccccccu)));
    v = _mm512_xor_si512(v, _mm512_and_si512(_mm512_slli_epi64(v, 4), I(0xf0f0f0f0u)));
    v = _mm512_xor_si512(v, _mm512_and_si512(_mm512_slli_epi64(v, 8), I(0xff00ff00u)));
    v = _mm512_and_si512(_mm512_xor_si512(v, _mm512_slli_epi64(v, 16)), lo32);
    return _mm512_xor_si512(_mm512_or_si512(_mm512_slli_epi64(x, 32), v), shift);
}

static inline __m512i bounce8(const lanes *L, __mmask8 cont, int sobol)
{
    if (!sobol)
        return bounce_bits8(L->job, L->depth);
    if (sobol == 2)
        return sobol8(L);
    int64_t __attribute__((aligned(64))) dep[8];
    uint64_t __attribute__((aligned(64))) u[8] = {0};
    _mm512_store_si512(dep, L->depth);
    for (__mmask8 m = cont; m; m &= m - 1) {
        const int l = __builtin_ctz(m);
        /* the vertex that ends segment dep - 1: trace2's brute-force layout */
        rt_sampler_seek(&lane_smp[l], RT_SAMPLER2_DIM_BOUNCE + RT_SAMPLER2_BOUNCE_DIMS * (uint32_t)(dep[l] - 1) +
                                          RT_SAMPLER2_SCATTER);
        u[l] = rt_sampler_get2d(&lane_smp[l]);
    }
    return _mm512_load_si512(u);
}

/* the lanes in `ended` take the next jobs (their camera rays), in lane
 * order; returns the lanes still live */
static __mmask8 refill8(lanes *L, __mmask8 live, __mmask8 ended, uint32_t *next, uint32_t njobs, int sobol)
{
    uint32_t k = (uint32_t)__builtin_popcount(ended);
    while (k > njobs - *next) { /* more ended lanes than jobs left: the highest go idle */
        const __mmask8 top = (__mmask8)(1u << (31 - __builtin_clz(ended)));
        ended &= (__mmask8)~top, live &= (__mmask8)~top, k--;
    }
    if (!ended)
        return live;
    const __m512i j = _mm512_add_epi64(_mm512_maskz_expand_epi64(ended, _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 6, 7)),
                                       _mm512_set1_epi64(*next));
    if (sobol == 1) {
        uint32_t jj = *next;
        for (__mmask8 m = ended; m; m &= m - 1)
            lane_sampler(__builtin_ctz(m), jj++);
    } else if (sobol == 2) { /* the lanes' keys and bit-reversed indices, as rt_sampler_start makes them */
        int64_t __attribute__((aligned(64))) key[8], rev[8];
        _mm512_store_si512(key, L->key);
        _mm512_store_si512(rev, L->rev);
        uint32_t jj = *next;
        for (__mmask8 m = ended; m; m &= m - 1, jj++) {
            const int l = __builtin_ctz(m);
            key[l] = (int64_t)mix64(jj / SPP + 42u);
            rev[l] = (int64_t)(rt_sampler_pair0(jj % SPP) >> 32);
        }
        L->key = _mm512_load_si512(key);
        L->rev = _mm512_load_si512(rev);
    }
    *next += k;
    const __m512d pix = _mm512_cvtepi64_pd(_mm512_srli_epi64(j, SPP_LOG2));
    const __m512d py =
        _mm512_roundscale_pd(_mm512_mul_pd(_mm512_add_pd(pix, B(0.5)), B(1.0 / W)), _MM_FROUND_TO_NEG_INF);
    const __m512d px = _mm512_sub_pd(pix, _mm512_mul_pd(py, B(W)));
    const __m512i r = mix8(_mm512_add_epi64(_mm512_mullo_epi64(j, I(0x9e3779b97f4a7c15ULL)), I(12345)));
    const __m512d lo = _mm512_cvtepu64_pd(_mm512_and_si512(r, I(0xffffffffULL)));
    const __m512d fx = _mm512_sub_pd(_mm512_mul_pd(lo, B(0x1.0p-32)), B(0.5));
    const __m512d fy = _mm512_sub_pd(_mm512_mul_pd(_mm512_cvtepu64_pd(_mm512_srli_epi64(r, 32)), B(0x1.0p-32)), B(0.5));
    const __m512d sx = _mm512_add_pd(px, fx), sy = _mm512_add_pd(py, fy);
#define CAM(c)                                                                                                 \
    _mm512_sub_pd(_mm512_add_pd(B(pix00.c), _mm512_add_pd(_mm512_mul_pd(B(du.c), sx), _mm512_mul_pd(B(dv.c), sy))), \
                  B(cam.c))
    L->dx = _mm512_mask_mov_pd(L->dx, ended, CAM(x));
    L->dy = _mm512_mask_mov_pd(L->dy, ended, CAM(y));
    L->dz = _mm512_mask_mov_pd(L->dz, ended, CAM(z));
#undef CAM
    L->ox = _mm512_mask_mov_pd(L->ox, ended, B(cam.x));
    L->oy = _mm512_mask_mov_pd(L->oy, ended, B(cam.y));
    L->oz = _mm512_mask_mov_pd(L->oz, ended, B(cam.z));
    L->tr = _mm512_mask_mov_pd(L->tr, ended, B(1));
    L->tg = _mm512_mask_mov_pd(L->tg, ended, B(1));
    L->tb = _mm512_mask_mov_pd(L->tb, ended, B(1));
    L->job = _mm512_mask_mov_epi64(L->job, ended, j);
    L->depth = _mm512_mask_mov_epi64(L->depth, ended, _mm512_setzero_si512());
    return live;
}

/* the light a lane found, into its pixel (rare: scalar) */
static void emit8(const lanes *L, __mmask8 light, __m512d em)
{
    double __attribute__((aligned(64))) r[8], g[8], b[8], e[8];
    int64_t __attribute__((aligned(64))) job[8];
    _mm512_store_pd(r, L->tr), _mm512_store_pd(g, L->tg), _mm512_store_pd(b, L->tb), _mm512_store_pd(e, em);
    _mm512_store_si512(job, L->job);
    for (__mmask8 m = light; m; m &= m - 1) {
        const int l = __builtin_ctz(m);
        add_light((uint32_t)job[l], r[l] * e[l], g[l] * e[l], b[l] * e[l]);
    }
}

static void render_lanes(int sobol)
{
    const uint32_t njobs = (uint32_t)(W * H * SPP);
    uint32_t next = 0;
    lanes L = {0};
    __mmask8 live = refill8(&L, 0xff, 0xff, &next, njobs, sobol);
    while (live) {
        segments += __builtin_popcount(live);
        __m512i id;
        const __m512d t = closest8(&L, &id);
        const __mmask8 hit = _mm512_mask_cmp_epi64_mask(live, id, _mm512_setzero_si512(), _MM_CMPINT_NLT);
        const __m512i idc = _mm512_max_epi64(id, _mm512_setzero_si512());
        const __m512d em = _mm512_i64gather_pd(idc, Q.em, 8);
        const __mmask8 light = _mm512_mask_cmp_pd_mask(hit, em, _mm512_setzero_pd(), _CMP_GT_OQ);
#ifdef PROBE_CHECK
        {
            const __m512i f = mix8(_mm512_xor_si512(_mm512_castpd_si512(t), bounce_bits8(L.job, L.depth)));
            uint64_t fl[8];
            _mm512_storeu_si512(fl, _mm512_maskz_mov_epi64(hit, f));
            for (int l = 0; l < 8; l++)
                fingerprint ^= fl[l];
        }
#endif
        L.depth = _mm512_add_epi64(L.depth, _mm512_set1_epi64(1));
        const __mmask8 deeper = _mm512_cmp_epi64_mask(L.depth, I(MAX_DEPTH), _MM_CMPINT_LT);
        const __mmask8 cont = hit & (__mmask8)~light & deeper;
        if (light)
            emit8(&L, light, em);
        /* the lambertian bounce: the normal facing the ray, plus a uniform direction */
        __m512d nx = _mm512_i64gather_pd(idc, Q.nx, 8), ny = _mm512_i64gather_pd(idc, Q.ny, 8);
        __m512d nz = _mm512_i64gather_pd(idc, Q.nz, 8);
        const __m512d den =
            _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(nx, L.dx), _mm512_mul_pd(ny, L.dy)), _mm512_mul_pd(nz, L.dz));
        const __mmask8 front = _mm512_cmp_pd_mask(den, _mm512_setzero_pd(), _CMP_LT_OQ);
        const __m512d flip = _mm512_mask_blend_pd(front, B(-1), B(1));
        nx = _mm512_mul_pd(nx, flip), ny = _mm512_mul_pd(ny, flip), nz = _mm512_mul_pd(nz, flip);
        L.ox = _mm512_add_pd(L.ox, _mm512_mul_pd(t, L.dx));
        L.oy = _mm512_add_pd(L.oy, _mm512_mul_pd(t, L.dy));
        L.oz = _mm512_add_pd(L.oz, _mm512_mul_pd(t, L.dz));
        lambert8(bounce8(&L, cont, sobol), nx, ny, nz, &L.dx, &L.dy, &L.dz);
        L.tr = _mm512_mul_pd(L.tr, _mm512_i64gather_pd(idc, Q.r, 8));
        L.tg = _mm512_mul_pd(L.tg, _mm512_i64gather_pd(idc, Q.g, 8));
        L.tb = _mm512_mul_pd(L.tb, _mm512_i64gather_pd(idc, Q.b, 8));
        const __mmask8 ended = live & (__mmask8)~cont;
        if (ended)
            live = refill8(&L, live, ended, &next, njobs, sobol);
    }
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char **argv)
{
    if (!__builtin_cpu_supports("avx512f") || !__builtin_cpu_supports("avx512dq")) {
        fprintf(stderr, "lockstep_probe: error: this CPU has no AVX-512 F and DQ\n");
        return 2;
    }
    const char *which = argc > 1 ? argv[1] : "lanes";
    cornell();
    pixels = calloc(W * H, sizeof *pixels);
    pixel_made = calloc(W * H, 1);
    const double t0 = now();
    if (!strcmp(which, "scalar"))
        render_scalar();
    else
        render_lanes(!strcmp(which, "sobol") ? 1 : !strcmp(which, "sobol8") ? 2 : 0);
    const double sec = now() - t0;
    double sum = 0;
    uint64_t hash = 0xcbf29ce484222325ULL; /* FNV-1a of the sums */
    for (int i = 0; i < W * H * 3; i++) {
        sum += (double)img[i] * 0x1.0p-32 / SPP;
        for (int k = 0; k < 8; k++)
            hash = (hash ^ (uint8_t)((uint64_t)img[i] >> (8 * k))) * 0x100000001b3ULL;
    }
    printf("%s: %.4f s, %ld segments, %.2f ns a segment, %.3f segments a path, image mean %.6f, image hash %016llx",
           which, sec, segments, sec / segments * 1e9, (double)segments / (W * H * SPP), sum / (W * H * 3),
           (unsigned long long)hash);
#ifdef PROBE_CHECK
    printf(", segments' fingerprint %016llx", (unsigned long long)fingerprint);
#endif
    printf("\n");
    return 0;
}
