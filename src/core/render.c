/* render.c - path tracing of the book's materials with an iterative loop
 * (no recursion, no allocation per ray), OpenMP over the pixels of a block. */
#include "render.h"
#include "core_internal.h"

#ifdef _OPENMP
#include <omp.h>
#endif

#include <math.h>
#include <pthread.h>
#include <string.h>

#include "bvh.h"
#include "mem.h"
#include "primary.h"
#include "status.h"

static inline int omp_thread(void)
{
#ifdef _OPENMP
    return omp_get_thread_num();
#else
    return 0;
#endif
}

/* Shadow-acne bias of the book. */
#define T_MIN 0.001
#define PACKET RT_RENDER_PACKET

int rt_render_init(rt_renderer *r, const rt_scene *s, const rt_accel *a, const rt_job *job)
{
    if (job->width == 0 || job->height == 0 || job->samples == 0 || job->max_depth == 0)
        return RT_EINVAL;
    r->scene = s;
    r->accel = a;
    r->job = *job;
    if (!r->job.roulette_depth)
        r->job.roulette_depth = RT_RENDER_ROULETTE_DEPTH;
    r->stop = NULL;
    r->bvh_avx = RT_BVH_HAVE_AVX ? rt_accel_bvh_avx(a) : NULL;
    r->primary = NULL;
    r->lay = rt_job_layout(job);
    return rt_camera_init(&r->camera, &s->camera, (double)job->width / (double)job->height);
}

/* The RNG key of pixel (x, y), shared by its samples. */
static inline uint64_t pixel_key(const rt_renderer *r, uint32_t x, uint32_t y)
{
    return rt_rng_pixel_key(r->job.seed, (uint64_t)y * r->job.width + x);
}

/* The camera ray of one sample of pixel (x, y) (key: pixel_key): starts
 * the sample's sampler *smp, which the rest of its path draws from. */
static inline __attribute__((always_inline)) rt_ray camera_ray(const rt_renderer *r, uint32_t x, uint32_t y,
                                                               uint64_t key, uint32_t sample, rt_sampler *smp)
{
    const uint32_t W = r->job.width, H = r->job.height;
    *smp = rt_sampler_start(r->job.sampler, key, sample);
    double du, dv;
    rt_sampler_pixel(smp, &du, &dv);
    /* The seed renderer's mapping: v counts rows from the bottom. */
    double u = ((double)x + du) / (double)(W > 1 ? W - 1 : 1);
    double v = ((double)(H - 1 - y) + dv) / (double)(H > 1 ? H - 1 : 1);
    if (r->camera.lens_radius > 0.0) { /* only then a lens sample (rt_camera_ray) */
        rt_vec3 d = rt_sampler_disk(smp);
        return rt_camera_ray_lens(&r->camera, u, v, d.x, d.y);
    }
    return rt_camera_ray_lens(&r->camera, u, v, 0.0, 0.0);
}

/* What a sample's path saw at its first non-specular hit (through glass
 * and perfect mirrors), for the denoiser's buffers: the surface's albedo
 * and shading normal; for a path that leaves into the sky first, the sky's
 * colour (at most 1) and a zero normal. A path that ends on the way (the
 * roulette, the depth limit) keeps the last specular surface's: glass's
 * albedo is 1, a mirror's its colour. done: found for good. */
typedef struct aov_rec {
    int done;
    rt_vec3 albedo, normal;
} aov_rec;

static inline double clamp01(double v) { return v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v; }

/* One segment of a path (the one at depth), after its closest-hit query
 * (found, *hit): a miss ends the path with the sky's light through
 * *throughput, into *color; a hit scatters *ray on into the next segment
 * and returns 1, unless the material absorbs it or the roulette ends the
 * path (it ends dark, *color stays black). aov, when not NULL, records the
 * first non-specular hit. */
static inline __attribute__((always_inline)) int path_step(const rt_renderer *r, rt_ray *ray, int found,
                                                           const rt_hit *hit, rt_sampler *smp, uint32_t depth,
                                                           rt_vec3 *throughput, rt_vec3 *color, aov_rec *aov)
{
    const rt_scene *s = r->scene;
    if (!found) {
        rt_vec3 ud = rt_v3_unit(ray->dir);
        double t = 0.5 * (ud.y + 1.0);
        rt_vec3 sky = rt_v3_add(rt_v3_scale(s->sky_bottom, 1.0 - t), rt_v3_scale(s->sky_top, t));
        *color = rt_v3_mul(*throughput, sky);
        if (aov && !aov->done)
            *aov = (aov_rec){1, rt_v3(clamp01(sky.x), clamp01(sky.y), clamp01(sky.z)), rt_v3(0, 0, 0)};
        return 0;
    }
    const rt_sphere *sp = &s->spheres[hit->prim];
    const rt_material *m = &s->materials[sp->material];
    rt_surface rec;
    rt_surface_from_sphere(&rec, sp, ray, hit->t);
    if (aov && !aov->done) {
        const int specular = m->kind == RT_MAT_DIELECTRIC || (m->kind == RT_MAT_METAL && m->fuzz == 0.0);
        *aov = (aov_rec){!specular, m->kind == RT_MAT_DIELECTRIC ? rt_v3(1, 1, 1) : m->albedo, rec.normal};
    }
    rt_vec3 att;
    rt_ray next;
    rt_sampler_bounce(smp, depth);
    if (!rt_material_scatter(m, ray, &rec, r->job.diffuse, smp, &att, &next))
        return 0;
    *throughput = rt_v3_mul(*throughput, att);
    *ray = next;
    if (r->job.roulette && depth + 1 >= r->job.roulette_depth) {
        /* Russian roulette: the path goes on with probability q, its
         * throughput divided by q, so its expectation is unchanged. q is
         * the throughput's largest channel over RT_RENDER_ROULETTE_KEEP
         * (at most 1): a path that can still bring that much light is
         * kept, and a survivor's throughput is at most that in every
         * channel, so the roulette never makes a sample brighter than the
         * sky (nothing for RT_SAMPLE_MAX to clip). */
        double q = throughput->x;
        q = throughput->y > q ? throughput->y : q;
        q = throughput->z > q ? throughput->z : q;
        q *= 1.0 / RT_RENDER_ROULETTE_KEEP;
        if (q < 1.0) {
            if (!(rt_sampler_roulette(smp) < q))
                return 0;
            *throughput = rt_v3_scale(*throughput, 1.0 / q);
        }
    }
    return 1;
}

/* The segments of a path from depth0 on, one after the other: its ray, RNG
 * and throughput so far; returns the light it brings. rays as for
 * trace_path; with avx, the closest hits come from the BVH's AVX traversal
 * (r->bvh_avx), and the caller must be compiled for AVX. */
static inline __attribute__((always_inline)) rt_vec3 trace_rest(const rt_renderer *r, rt_ray ray, rt_sampler *smp,
                                                                rt_vec3 throughput, uint32_t depth0,
                                                                uint64_t *segments, rt_ray *rays, const int avx,
                                                                uint32_t pfirst, int32_t pn, aov_rec *aov)
{
    rt_vec3 color = rt_v3(0, 0, 0);
    uint64_t segs = 0;
    for (uint32_t depth = depth0; depth < r->job.max_depth; depth++) {
        rt_hit hit;
        if (rays)
            rays[segs] = ray;
        segs++;
        /* A camera ray (depth 0) of a pixel with a list takes its hit from
         * the list (pn >= 0; the packet loop's continuations pass it too,
         * for groups of one sample). Taking that first segment out of this
         * loop instead, and the argument with it, made the whole render
         * 0.988 to 0.994 as fast over five variants (ab_render.sh, 11
         * rounds each, against 1.000 for the same code): the compiler lays
         * out the inlined path loop worse, and the branch here is taken or
         * not for a whole path at a time. */
        int found;
        if (depth == 0 && pn >= 0)
            found = rt_primary_closest(r->primary, pfirst, pn, &ray, T_MIN, INFINITY, &hit);
        else
#if RT_BVH_HAVE_AVX
            found = avx ? rt_bvh_closest_avx(r->bvh_avx, &ray, T_MIN, INFINITY, &hit)
                        : rt_accel_closest(r->accel, &ray, T_MIN, INFINITY, &hit);
#else
            found = rt_accel_closest(r->accel, &ray, T_MIN, INFINITY, &hit);
        (void)avx;
#endif
        if (!path_step(r, &ray, found, &hit, smp, depth, &throughput, &color, aov))
            break;
    }
    *segments += segs;
    return color;
}

/* One sample's path from its camera ray, one segment after the other;
 * when rays is not NULL, every ray traced is stored there (rt_render_sample
 * passes NULL, and the stores fold away). */
static inline __attribute__((always_inline)) rt_vec3 trace_path(const rt_renderer *r, rt_ray ray, rt_sampler *smp,
                                                                uint64_t *segments, rt_ray *rays, uint32_t pfirst,
                                                                int32_t pn, aov_rec *aov)
{
    rt_vec3 throughput = rt_v3(1, 1, 1);
    return trace_rest(r, ray, smp, throughput, 0, segments, rays, 0, pfirst, pn, aov);
}

/* The camera rays' list of pixel (x, y) (rt_primary_tile), -1 for none. */
static inline int32_t primary_list(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t *first)
{
    *first = 0;
    return r->primary ? rt_primary_tile(r->primary, x, y, first) : -1;
}

rt_vec3 rt_render_sample(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t sample, uint64_t *segments)
{
    rt_sampler smp;
    rt_ray ray = camera_ray(r, x, y, pixel_key(r, x, y), sample, &smp);
    uint32_t pfirst;
    int32_t pn = primary_list(r, x, y, &pfirst);
    return trace_path(r, ray, &smp, segments, NULL, pfirst, pn, NULL);
}

uint32_t rt_render_sample_rays(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t sample, rt_ray *rays)
{
    uint64_t segs = 0;
    rt_sampler smp;
    rt_ray ray = camera_ray(r, x, y, pixel_key(r, x, y), sample, &smp);
    uint32_t pfirst;
    int32_t pn = primary_list(r, x, y, &pfirst);
    trace_path(r, ray, &smp, &segs, rays, pfirst, pn, NULL);
    return (uint32_t)segs;
}

/* A pixel's sums while its samples are traced: fixed-point colour, and
 * the denoiser's buffers when asked for. */
typedef struct pixel_acc {
    int64_t c[3], aov[6];
} pixel_acc;

static inline int64_t fix_signed(double v) { return v < 0.0 ? -rt_render_fix(-v) : rt_render_fix(v); }

/* Adds one sample: its light, and what its path saw first (aov, or NULL). */
static inline void add_sample(pixel_acc *a, rt_vec3 c, const aov_rec *aov)
{
    a->c[0] += rt_render_fix(c.x);
    a->c[1] += rt_render_fix(c.y);
    a->c[2] += rt_render_fix(c.z);
    if (aov) {
        a->aov[0] += rt_render_fix(aov->albedo.x);
        a->aov[1] += rt_render_fix(aov->albedo.y);
        a->aov[2] += rt_render_fix(aov->albedo.z);
        a->aov[3] += fix_signed(aov->normal.x);
        a->aov[4] += fix_signed(aov->normal.y);
        a->aov[5] += fix_signed(aov->normal.z);
    }
}

uint32_t rt_render_adapt_count(double sum, double sum2, uint32_t n, double threshold, uint32_t samples)
{
    const double mean = sum / n, ref = mean > RT_ADAPT_FLOOR ? mean : RT_ADAPT_FLOOR;
    double var = (sum2 - sum * mean) / (double)(n - 1);
    var = var > 0.0 ? var : 0.0;
    /* the standard error of the mean of m samples is sqrt(var / m) */
    const double need = var / (threshold * ref * threshold * ref);
    uint32_t m = RT_ADAPT_FIRST;
    while (m < samples && (double)m < need)
        m *= 2;
    return m < samples ? m : samples;
}

/* The luminance of a sample as its fixed-point colour has it. */
static inline double luminance(rt_vec3 c)
{
    /* exact in a double: each is below 2^42 */
    return (double)(rt_render_fix(c.x) + rt_render_fix(c.y) + rt_render_fix(c.z)) * (1.0 / (3.0 * RT_FIX_ONE));
}

/* rt_render_pilot, for a pixel whose camera-ray list is known. */
static uint32_t pilot_count(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t pfirst, int32_t pn,
                            uint64_t *segments)
{
    /* the pixel's key for a seed of their own: numbers independent of its
     * samples' */
    const uint64_t key = rt_rng_pixel_key(r->job.seed ^ RT_ADAPT_PILOT_SALT, (uint64_t)y * r->job.width + x);
    double l = 0, l2 = 0;
    for (uint32_t k = 0; k < RT_ADAPT_FIRST; k++) {
        rt_sampler smp;
        rt_ray cam = camera_ray(r, x, y, key, k, &smp);
        const double v = luminance(trace_path(r, cam, &smp, segments, NULL, pfirst, pn, NULL));
        l += v;
        l2 += v * v;
    }
    return rt_render_adapt_count(l, l2, RT_ADAPT_FIRST, r->job.noise_threshold, r->job.samples);
}

uint32_t rt_render_pilot(const rt_renderer *r, uint32_t x, uint32_t y, uint64_t *segments)
{
    uint32_t pfirst;
    const int32_t pn = primary_list(r, x, y, &pfirst);
    return pilot_count(r, x, y, pfirst, pn, segments);
}

/* The samples s0..s1-1 of pixel (x, y) added in fixed point to px (the
 * pixel's values, r->lay); with adaptive sampling only those below the
 * pixel's count (rt_render_pilot), and the count of them. extras: the job may have adaptive
 * sampling or buffers (r->lay.ch > 3); a constant, so that the path loop
 * of a plain job has none of their code (+3.1 % instructions with it). */
static inline __attribute__((always_inline)) uint64_t pixel(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t s0,
                                                            uint32_t s1, int64_t *px, const int avx, const int extras)
{
    pixel_acc acc; /* a local, kept in registers */
    memset(&acc, 0, sizeof acc);
    uint64_t segs = 0;
    const uint64_t key = pixel_key(r, x, y);
    uint32_t pfirst;
    const int32_t pn = primary_list(r, x, y, &pfirst);
    const int adapt = extras && r->lay.count != 0, aovs = extras && (r->lay.albedo || r->lay.normal);
    if (adapt) { /* the pixel takes samples [0, its count) */
        const uint32_t n = pilot_count(r, x, y, pfirst, pn, &segs);
        s1 = s1 < n ? s1 : n;
        s0 = s0 < s1 ? s0 : s1;
    }
    uint32_t s = s0;
#if RT_BVH_HAVE_AVX
    if (avx) {
        /* PACKET samples at a time, their paths advanced a segment each
         * in turn. The camera rays are nearly the same ray, and so, less
         * so, are the next segments while all the paths live: those go to
         * the BVH as one packet (one traversal for all, the rays in AVX
         * lanes), the others one at a time, which measured faster
         * (ab_render.sh: packets for every segment of two or more live
         * paths 0.94, for all eight 1.05). Each ray gets the hit its own
         * traversal would find (rt_sphere_closer's rule), and each path
         * draws from its own RNG, so the pixels are the same bits as from
         * trace_path (the same numbers in the same order, roulette
         * included). */
        while (s < s1) {
            const int n = s1 - s < PACKET ? (int)(s1 - s) : PACKET, all = (1 << n) - 1;
            rt_ray ray[PACKET];
            rt_sampler smp[PACKET];
            rt_hit hit[PACKET];
            rt_vec3 thr[PACKET], col[PACKET];
            aov_rec aov[PACKET];
            for (int k = 0; k < n; k++) {
                ray[k] = camera_ray(r, x, y, key, s + (uint32_t)k, &smp[k]);
                thr[k] = rt_v3(1, 1, 1);
                col[k] = rt_v3(0, 0, 0);
                aov[k] = (aov_rec){0, {0, 0, 0}, {0, 0, 0}};
            }
            /* Packets while no path has ended, so ray[0, n) is the packet. */
            int live = all;
            uint32_t depth = 0;
            for (; depth < r->job.max_depth && rt_render_in_packet(n, live == all, depth); depth++) {
                int found = 0;
                if (depth == 0 && pn >= 0)
                    for (int k = 0; k < n; k++)
                        found |= rt_primary_closest(r->primary, pfirst, pn, &ray[k], T_MIN, INFINITY, &hit[k]) << k;
                else
                    found = rt_bvh_closest_packet_avx(r->bvh_avx, ray, n, T_MIN, INFINITY, hit);
                segs += (uint64_t)n;
                /* the hits, then the misses: two loops over bit masks
                 * instead of a branch on hit or miss in every lane */
                for (int m = found; m; m &= m - 1) {
                    const int k = __builtin_ctz((unsigned)m);
                    if (!path_step(r, &ray[k], 1, &hit[k], &smp[k], depth, &thr[k], &col[k], aovs ? &aov[k] : NULL))
                        live &= ~(1 << k);
                }
                for (int m = all & ~found; m; m &= m - 1) {
                    const int k = __builtin_ctz((unsigned)m);
                    path_step(r, &ray[k], 0, &hit[k], &smp[k], depth, &thr[k], &col[k], aovs ? &aov[k] : NULL);
                    live &= ~(1 << k);
                }
            }
            /* The paths still live go on one at a time, each to its end:
             * consecutive segments of a path start where the last one
             * ended, which keeps the traversal's memory and branch history
             * warm better than taking the paths in turn. */
            for (; live; live &= live - 1) {
                const int k = __builtin_ctz((unsigned)live);
                col[k] = trace_rest(r, ray[k], &smp[k], thr[k], depth, &segs, NULL, 1, pfirst, pn,
                                    aovs ? &aov[k] : NULL);
            }
            for (int k = 0; k < n; k++)
                add_sample(&acc, col[k], aovs ? &aov[k] : NULL);
            s += (uint32_t)n;
        }
    } else
#else
    (void)avx;
#endif
        for (; s < s1; s++) {
            rt_sampler smp;
            rt_ray cam = camera_ray(r, x, y, key, s, &smp);
            aov_rec aov = {0, {0, 0, 0}, {0, 0, 0}};
            add_sample(&acc, trace_path(r, cam, &smp, &segs, NULL, pfirst, pn, aovs ? &aov : NULL),
                       aovs ? &aov : NULL);
        }
    px[0] += acc.c[0];
    px[1] += acc.c[1];
    px[2] += acc.c[2];
    if (adapt)
        px[r->lay.count] += s - s0;
    if (aovs && r->lay.albedo)
        for (int k = 0; k < 3; k++)
            px[r->lay.albedo + k] += acc.aov[k];
    if (aovs && r->lay.normal)
        for (int k = 0; k < 3; k++)
            px[r->lay.normal + k] += acc.aov[3 + k];
    return segs;
}

/* The path loop, twice: in the baseline instruction set, and compiled for
 * AVX with the BVH's AVX traversal inlined (no fused multiply-add in either:
 * every operation rounds the same, so the pixels are the same bits; the
 * determinism test compares the two). flatten inlines the whole path loop
 * into each, the intersector included: 5.7 % faster renders than calling
 * the AVX traversal out of line (scripts/ab_render.sh, 1.057 twice). Each
 * twice again: for plain jobs, and for jobs with adaptive sampling or
 * buffers (pixel's extras). */
typedef uint64_t (*pixel_fn)(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t s0, uint32_t s1, int64_t *px);

__attribute__((flatten)) static uint64_t pixel_base(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t s0,
                                                    uint32_t s1, int64_t *px)
{
    return pixel(r, x, y, s0, s1, px, 0, 0);
}

__attribute__((flatten)) static uint64_t pixel_base_x(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t s0,
                                                      uint32_t s1, int64_t *px)
{
    return pixel(r, x, y, s0, s1, px, 0, 1);
}

#if RT_BVH_HAVE_AVX
__attribute__((target("avx"), flatten)) static uint64_t pixel_avx(const rt_renderer *r, uint32_t x, uint32_t y,
                                                                   uint32_t s0, uint32_t s1, int64_t *px)
{
    return pixel(r, x, y, s0, s1, px, 1, 0);
}

__attribute__((target("avx"), flatten)) static uint64_t pixel_avx_x(const rt_renderer *r, uint32_t x, uint32_t y,
                                                                     uint32_t s0, uint32_t s1, int64_t *px)
{
    return pixel(r, x, y, s0, s1, px, 1, 1);
}
#endif

/* The path loop for r's job and CPU. */
static pixel_fn pixel_for(const rt_renderer *r)
{
    const int extras = r->lay.ch > 3;
#if RT_BVH_HAVE_AVX
    if (r->bvh_avx)
        return extras ? pixel_avx_x : pixel_avx;
#endif
    return extras ? pixel_base_x : pixel_base;
}

static int stopped(const rt_renderer *r)
{
    return r->stop && *r->stop;
}

/* Pixel i of a block of columns [x0, x0 + w) and rows from y0, row by
 * row: its samples [s0, s1) added to acc[ch i ..]; returns the ray
 * segments traced. */
static inline uint64_t add_pixel(const rt_renderer *r, pixel_fn fn, uint32_t x0, uint32_t w, uint32_t y0,
                                 uint32_t s0, uint32_t s1, long i, int64_t *acc)
{
    uint32_t x = x0 + (uint32_t)(i % w), y = y0 + (uint32_t)(i / w);
    return fn(r, x, y, s0, s1, acc + i * r->lay.ch);
}

uint64_t rt_render_rows(const rt_renderer *r, uint32_t y0, uint32_t y1, uint32_t s0, uint32_t s1, int64_t *acc,
                        int nthreads)
{
    const uint32_t W = r->job.width;
    const long npix = (long)(y1 - y0) * W;
    uint64_t total = 0;
    pixel_fn fn = pixel_for(r);
#ifdef _OPENMP
    if (nthreads <= 0)
        nthreads = omp_get_max_threads();
#else
    (void)nthreads;
#endif
    /* guided: each thread starts on a long run of neighbouring pixels and
     * the runs shrink (to 4 pixels) towards the end of the block. */
#pragma omp parallel for schedule(guided, 4) reduction(+ : total) num_threads(nthreads) if (nthreads > 1)
    for (long i = 0; i < npix; i++)
        if (!stopped(r))
            total += add_pixel(r, fn, 0, W, y0, s0, s1, i, acc);
    return total;
}

/* ---- a stream of units ---------------------------------------------------- */

typedef struct stream_unit {
    rt_unit u;
    int64_t *buf;
    size_t cap;                 /* entries of buf */
    long npix, next, left;      /* pixels: in all, next to give out, not yet rendered */
    uint64_t segments, order;   /* order: when it was taken */
    int held;
} stream_unit;

typedef struct stream {
    const rt_renderer *r;
    const rt_render_source *src;
    pixel_fn fn;
    int threads, status, exhausted;
    uint64_t taken;
    pthread_mutex_t mu;      /* everything below */
    pthread_cond_t freed;    /* a unit was handed on, or a thread left */
    pthread_mutex_t done_mu; /* src->done one call at a time */
    stream_unit units[RT_RENDER_STREAM_UNITS];
    int n_units;
} stream;

/* The next run of pixels for the calling thread, under st->mu: from the
 * oldest unit in hand that has pixels left, else from a new unit; waits
 * while every unit is given out and none can be taken. Returns the unit,
 * or NULL when there is nothing more to do. */
static stream_unit *stream_claim(stream *st, int master, long *a, long *b)
{
    for (;;) {
        if (st->status || stopped(st->r))
            return NULL;
        stream_unit *best = NULL, *empty = NULL;
        for (int k = 0; k < st->n_units; k++) {
            stream_unit *su = &st->units[k];
            if (!su->held)
                empty = empty ? empty : su;
            else if (su->next < su->npix && (!best || su->order < best->order))
                best = su;
        }
        rt_unit u;
        int got = 0;
        if (!best && !st->exhausted && empty && (got = st->src->take(st->src->ctx, &u)) == 0) {
            st->exhausted = 1;
            continue;
        }
        if (got > 0) {
            size_t need = (size_t)rt_unit_pixels(&u) * st->r->lay.ch;
            if (need > empty->cap) { /* the first units are the largest (schedule.h) */
                rt_mem_free(empty->buf, empty->cap * sizeof *empty->buf);
                empty->cap = 0;
                if (!(empty->buf = rt_mem_zeroed(need * sizeof *empty->buf))) {
                    st->status = RT_ENOMEM;
                    return NULL;
                }
                empty->cap = need;
            }
            empty->u = u;
            empty->npix = empty->left = (long)rt_unit_pixels(&u);
            empty->next = 0;
            empty->segments = 0;
            empty->order = st->taken++;
            empty->held = 1;
            best = empty;
        }
        if (best) {
            /* guided: runs shrink as the unit's pixels run out, so its
             * last runs are short; neighbours stay on one thread. (Runs of
             * rest / threads, OpenMP's guided rule: ab_render.sh -j 2 0.993,
             * no difference.) */
            long rest = best->npix - best->next, n = rest / (2 * st->threads);
            n = n < 4 ? 4 : n;
            *a = best->next;
            *b = best->next = best->next + (n < rest ? n : rest);
            return best;
        }
        if (st->exhausted)
            return NULL; /* the last units' runs are all given out (or none is left) */
        if (master && st->src->poll) {
            /* the master keeps the source's communication going while it
             * waits: for a unit, or for a unit in hand to be done */
            pthread_mutex_unlock(&st->mu);
            int more = st->src->poll(st->src->ctx, 1);
            pthread_mutex_lock(&st->mu);
            if (more)
                pthread_cond_broadcast(&st->freed);
        } else {
            pthread_cond_wait(&st->freed, &st->mu);
        }
    }
}

static void stream_thread(stream *st)
{
    const rt_renderer *r = st->r;
    const int master = omp_thread() == 0;
    pthread_mutex_lock(&st->mu);
    long a, b;
    stream_unit *su;
    while ((su = stream_claim(st, master, &a, &b))) {
        pthread_mutex_unlock(&st->mu);
        uint64_t segs = 0;
        for (long i = a; i < b && !stopped(r); i++) {
            segs += add_pixel(r, st->fn, su->u.x0, su->u.x1 - su->u.x0, su->u.y0, su->u.s0, su->u.s1, i, su->buf);
            /* the master polls after every pixel (the source decides how
             * often to really look), and so right after a unit is done:
             * its next pixel, or its idle poll in stream_claim */
            if (master && st->src->poll && st->src->poll(st->src->ctx, 0)) {
                pthread_mutex_lock(&st->mu); /* so that a thread between take and its wait cannot miss it */
                pthread_cond_broadcast(&st->freed);
                pthread_mutex_unlock(&st->mu);
            }
        }
        pthread_mutex_lock(&st->mu);
        su->segments += segs;
        su->left -= b - a;
        if (su->left == 0) {
            pthread_mutex_unlock(&st->mu);
            const size_t n = (size_t)su->npix * r->lay.ch;
            if (!stopped(r)) {
                pthread_mutex_lock(&st->done_mu);
                st->src->done(st->src->ctx, &su->u, su->buf, su->segments);
                pthread_mutex_unlock(&st->done_mu);
            }
            memset(su->buf, 0, n * sizeof *su->buf); /* for the next unit */
            pthread_mutex_lock(&st->mu);
            su->held = 0;
            pthread_cond_broadcast(&st->freed);
        }
    }
    pthread_cond_broadcast(&st->freed); /* a waiting thread may have to leave too */
    pthread_mutex_unlock(&st->mu);
}

int rt_render_stream(const rt_renderer *r, int nthreads, const rt_render_source *src)
{
#ifdef _OPENMP
    if (nthreads <= 0)
        nthreads = omp_get_max_threads();
#else
    nthreads = 1;
#endif
    stream st;
    memset(&st, 0, sizeof st);
    st.r = r;
    st.src = src;
    st.fn = pixel_for(r);
    st.threads = nthreads;
    /* one unit more than threads, so that a thread that has finished its
     * runs can always start on a new unit while the others finish theirs */
    st.n_units = nthreads + 1 < RT_RENDER_STREAM_UNITS ? nthreads + 1 : RT_RENDER_STREAM_UNITS;
    pthread_mutex_init(&st.mu, NULL);
    pthread_mutex_init(&st.done_mu, NULL);
    pthread_cond_init(&st.freed, NULL);
#pragma omp parallel num_threads(nthreads) if (nthreads > 1)
    stream_thread(&st);
    pthread_cond_destroy(&st.freed);
    pthread_mutex_destroy(&st.done_mu);
    pthread_mutex_destroy(&st.mu);
    for (int k = 0; k < st.n_units; k++)
        rt_mem_free(st.units[k].buf, st.units[k].cap * sizeof *st.units[k].buf);
    return st.status;
}
