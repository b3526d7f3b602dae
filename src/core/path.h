/* path.h - the path integrator: a sample's camera ray, its path's segments
 * one after the other (the book's materials, the sky, the roulette) and a
 * pixel's samples summed in fixed point, alone or eight paths at a time in
 * BVH packets. Everything is static inline so that each of dispatch.c's
 * path loops (one per instruction set and job kind) gets its own copy with
 * the intersector inlined; render.c compiles it once more for the single
 * samples the tests and benchmarks ask for. Included by those two files
 * only. */
#ifndef RT_PATH_H
#define RT_PATH_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "bvh.h"
#include "core_internal.h"
#include "primary.h"
#include "render.h"

/* Shadow-acne bias of the book. */
#define T_MIN 0.001

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

/* What every path of one pixel shares. aovs: the paths record aov_rec
 * (a constant 0 in the plain path loops, so their code folds away). */
typedef struct pixel_ctx {
    const rt_renderer *r;
    uint32_t x, y;
    rt_sampler_pixel smp; /* the pixel's sampler */
    uint32_t pfirst; /* its camera rays' list (primary_list), pn < 0: none */
    int32_t pn;
    int aovs;
} pixel_ctx;

/* The integrator's state of one path in flight: the ray of its next
 * segment, the numbers it draws, its throughput so far, the light it has
 * brought, and what it saw first. */
typedef struct path {
    rt_ray ray;
    rt_sampler smp;
    rt_vec3 thr, col;
    aov_rec aov;
} path;

static inline double clamp01(double v) { return v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v; }

/* The RNG key of pixel (x, y), shared by its samples. */
static inline uint64_t pixel_key(const rt_renderer *r, uint32_t x, uint32_t y)
{
    return rt_rng_pixel_key(r->job.seed, (uint64_t)y * r->job.width + x);
}

/* The camera rays' list of pixel (x, y) (rt_primary_tile), -1 for none. */
static inline int32_t primary_list(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t *first)
{
    *first = 0;
    return r->primary ? rt_primary_tile(r->primary, x, y, first) : -1;
}

/* Pixel (x, y)'s context, its samples drawn with key. */
static inline pixel_ctx pixel_start(const rt_renderer *r, uint32_t x, uint32_t y, uint64_t key, int aovs)
{
    pixel_ctx pc;
    pc.r = r;
    pc.x = x;
    pc.y = y;
    rt_sampler_for_pixel(&pc.smp, r->job.sampler, key);
    pc.pn = primary_list(r, x, y, &pc.pfirst);
    pc.aovs = aovs;
    return pc;
}

/* A new path: the camera ray of sample `sample` of pc's pixel, which
 * starts the sample's sampler, which the rest of the path draws from. */
static inline __attribute__((always_inline)) void path_start(const pixel_ctx *pc, uint32_t sample, path *p)
{
    const rt_renderer *r = pc->r;
    const uint32_t W = r->job.width, H = r->job.height;
    p->smp = rt_sampler_start(&pc->smp, sample);
    p->thr = rt_v3(1, 1, 1);
    p->col = rt_v3(0, 0, 0);
    p->aov = (aov_rec){0, {0, 0, 0}, {0, 0, 0}};
    double du, dv;
    rt_sampler_pixel2d(&p->smp, &du, &dv);
    /* The seed renderer's mapping: v counts rows from the bottom. */
    double u = ((double)pc->x + du) / (double)(W > 1 ? W - 1 : 1);
    double v = ((double)(H - 1 - pc->y) + dv) / (double)(H > 1 ? H - 1 : 1);
    if (r->camera.lens_radius > 0.0) { /* only then a lens sample (rt_camera_ray) */
        rt_vec3 d = rt_sampler_lens(&p->smp);
        p->ray = rt_camera_ray_lens(&r->camera, u, v, d.x, d.y);
    } else {
        p->ray = rt_camera_ray_lens(&r->camera, u, v, 0.0, 0.0);
    }
}

/* The sky's light for a path that leaves the scene. */
static inline __attribute__((always_inline)) void path_sky(const pixel_ctx *pc, path *p)
{
    const rt_scene *s = pc->r->scene;
    rt_vec3 ud = rt_v3_unit(p->ray.dir);
    double t = 0.5 * (ud.y + 1.0);
    rt_vec3 sky = rt_v3_add(rt_v3_scale(s->sky_bottom, 1.0 - t), rt_v3_scale(s->sky_top, t));
    p->col = rt_v3_mul(p->thr, sky);
    if (pc->aovs && !p->aov.done)
        p->aov = (aov_rec){1, rt_v3(clamp01(sky.x), clamp01(sky.y), clamp01(sky.z)), rt_v3(0, 0, 0)};
}

/* Russian roulette after the bounce at depth: the path goes on with
 * probability q, its throughput divided by q, so its expectation is
 * unchanged. q is the throughput's largest channel over
 * RT_RENDER_ROULETTE_KEEP (at most 1): a path that can still bring that
 * much light is kept, and a survivor's throughput is at most that in every
 * channel, so the roulette never makes a sample brighter than the sky
 * (nothing for RT_SAMPLE_MAX to clip). Returns 0 when the path ends. */
static inline __attribute__((always_inline)) int path_roulette(const rt_renderer *r, path *p, uint32_t depth)
{
    if (!r->job.roulette || depth + 1 < r->job.roulette_depth)
        return 1;
    double q = p->thr.x;
    q = p->thr.y > q ? p->thr.y : q;
    q = p->thr.z > q ? p->thr.z : q;
    q *= 1.0 / RT_RENDER_ROULETTE_KEEP;
    if (q < 1.0) {
        if (!(rt_sampler_get1d(&p->smp) < q))
            return 0;
        p->thr = rt_v3_scale(p->thr, 1.0 / q);
    }
    return 1;
}

/* One segment of a path (the one at depth), after its closest-hit query
 * (found, *hit): a miss ends the path with the sky's light through its
 * throughput; a hit scatters the ray on into the next segment and returns
 * 1, unless the material absorbs it or the roulette ends the path (it ends
 * dark). */
static inline __attribute__((always_inline)) int path_step(const pixel_ctx *pc, path *p, int found,
                                                           const rt_hit *hit, uint32_t depth)
{
    const rt_renderer *r = pc->r;
    if (!found) {
        path_sky(pc, p);
        return 0;
    }
    const rt_sphere *sp = &r->scene->spheres[hit->prim];
    const rt_material *m = &r->scene->materials[sp->material];
    rt_surface rec;
    rt_surface_from_sphere(&rec, sp, &p->ray, hit->t);
    if (pc->aovs && !p->aov.done) {
        const int specular = m->kind == RT_MAT_DIELECTRIC || (m->kind == RT_MAT_METAL && m->fuzz == 0.0);
        p->aov = (aov_rec){!specular, m->kind == RT_MAT_DIELECTRIC ? rt_v3(1, 1, 1) : m->albedo, rec.normal};
    }
    rt_vec3 att;
    rt_ray next;
    rt_sampler_bounce(&p->smp, depth);
    if (!rt_material_scatter(m, &p->ray, &rec, r->job.diffuse, &p->smp, &att, &next))
        return 0;
    p->thr = rt_v3_mul(p->thr, att);
    p->ray = next;
    return path_roulette(r, p, depth);
}

/* The segments of path p from depth0 on, one after the other, to its end
 * (its light in p->col); adds them to *segments. When rays is not NULL,
 * every ray traced is stored there (rt_render_sample passes NULL, and the
 * stores fold away). With avx, the closest hits come from the BVH's AVX
 * traversal (r->bvh_avx), and the caller must be compiled for AVX. */
static inline __attribute__((always_inline)) void path_trace(const pixel_ctx *pc, path *p, uint32_t depth0,
                                                             uint64_t *segments, rt_ray *rays, const int avx)
{
    const rt_renderer *r = pc->r;
    uint64_t segs = 0;
    for (uint32_t depth = depth0; depth < r->job.max_depth; depth++) {
        rt_hit hit;
        if (rays)
            rays[segs] = p->ray;
        segs++;
        /* A camera ray (depth 0) of a pixel with a list takes its hit from
         * the list (pn >= 0; the packet loop's continuations pass it too,
         * for groups of one sample). Taking that first segment out of this
         * loop instead made the whole render 0.988 to 0.994 as fast over
         * five variants (ab_render.sh, 11 rounds each, against 1.000 for
         * the same code): the compiler lays out the inlined path loop
         * worse, and the branch here is taken or not for a whole path at
         * a time. */
        int found;
        if (depth == 0 && pc->pn >= 0)
            found = rt_primary_closest(r->primary, pc->pfirst, pc->pn, &p->ray, T_MIN, INFINITY, &hit);
        else
#if RT_BVH_HAVE_AVX
            found = avx ? rt_bvh_closest_avx(r->bvh_avx, &p->ray, T_MIN, INFINITY, &hit)
                        : rt_accel_closest(r->accel, &p->ray, T_MIN, INFINITY, &hit);
#else
            found = rt_accel_closest(r->accel, &p->ray, T_MIN, INFINITY, &hit);
        (void)avx;
#endif
        if (!path_step(pc, p, found, &hit, depth))
            break;
    }
    *segments += segs;
}

/* ---- a pixel's samples ---------------------------------------------------- */

/* A pixel's sums while its samples are traced: fixed-point colour, and
 * the denoiser's buffers when asked for. */
typedef struct pixel_acc {
    int64_t c[3], aov[6];
} pixel_acc;

static inline int64_t fix_signed(double v) { return v < 0.0 ? -rt_render_fix(-v) : rt_render_fix(v); }

/* Adds one finished path: its light, and what it saw first (with aovs). */
static inline void add_sample(pixel_acc *a, const path *p, int aovs)
{
    a->c[0] += rt_render_fix(p->col.x);
    a->c[1] += rt_render_fix(p->col.y);
    a->c[2] += rt_render_fix(p->col.z);
    if (aovs) {
        a->aov[0] += rt_render_fix(p->aov.albedo.x);
        a->aov[1] += rt_render_fix(p->aov.albedo.y);
        a->aov[2] += rt_render_fix(p->aov.albedo.z);
        a->aov[3] += fix_signed(p->aov.normal.x);
        a->aov[4] += fix_signed(p->aov.normal.y);
        a->aov[5] += fix_signed(p->aov.normal.z);
    }
}

/* The luminance of a sample as its fixed-point colour has it. */
static inline double luminance(rt_vec3 c)
{
    /* exact in a double: each is below 2^42 */
    return (double)(rt_render_fix(c.x) + rt_render_fix(c.y) + rt_render_fix(c.z)) * (1.0 / (3.0 * RT_FIX_ONE));
}

/* The sample count of pixel (x, y) from its pilot (render.h); pc: the
 * pixel's context for its own samples (its camera rays' list). */
static inline uint32_t pilot_count(const pixel_ctx *pc, uint64_t *segments)
{
    const rt_renderer *r = pc->r;
    /* the pixel's key for a seed of their own: numbers independent of its
     * samples' */
    pixel_ctx pilot = *pc;
    rt_sampler_for_pixel(&pilot.smp, r->job.sampler,
                         rt_rng_pixel_key(r->job.seed ^ RT_ADAPT_PILOT_SALT, (uint64_t)pc->y * r->job.width + pc->x));
    pilot.aovs = 0;
    double l = 0, l2 = 0;
    for (uint32_t k = 0; k < RT_ADAPT_FIRST; k++) {
        path p;
        path_start(&pilot, k, &p);
        path_trace(&pilot, &p, 0, segments, NULL, 0);
        const double v = luminance(p.col);
        l += v;
        l2 += v * v;
    }
    return rt_render_adapt_count(l, l2, RT_ADAPT_FIRST, r->job.noise_threshold, r->job.samples);
}

#if RT_BVH_HAVE_AVX
/* Samples [s, s + n) of pc's pixel (n <= RT_RENDER_PACKET), their paths
 * advanced a segment each in turn. The camera rays are nearly the same
 * ray, and so, less so, are the next segments while all the paths live:
 * those go to the BVH as one packet (one traversal for all, the rays in
 * AVX lanes), the others one at a time, which measured faster
 * (ab_render.sh: packets for every segment of two or more live paths 0.94,
 * for all eight 1.05). Each ray gets the hit its own traversal would find
 * (rt_sphere_closer's rule), and each path draws from its own numbers, so
 * the pixels are the same bits as from path_trace alone (the same numbers
 * in the same order, roulette included). Caller compiled for AVX. */
static inline __attribute__((always_inline)) void pixel_packet(const pixel_ctx *pc, uint32_t s, int n,
                                                               pixel_acc *acc, uint64_t *segs)
{
    const rt_renderer *r = pc->r;
    const int all = (1 << n) - 1;
    path p[RT_RENDER_PACKET];
    rt_ray ray[RT_RENDER_PACKET];
    rt_hit hit[RT_RENDER_PACKET];
    for (int k = 0; k < n; k++)
        path_start(pc, s + (uint32_t)k, &p[k]);
    /* Packets while no path has ended, so the n rays are the packet. */
    int live = all;
    uint32_t depth = 0;
    for (; depth < r->job.max_depth && rt_render_in_packet(n, live == all, depth); depth++) {
        int found = 0;
        if (depth == 0 && pc->pn >= 0)
            for (int k = 0; k < n; k++)
                found |= rt_primary_closest(r->primary, pc->pfirst, pc->pn, &p[k].ray, T_MIN, INFINITY, &hit[k])
                         << k;
        else {
            for (int k = 0; k < n; k++)
                ray[k] = p[k].ray;
            found = rt_bvh_closest_packet_avx(r->bvh_avx, ray, n, T_MIN, INFINITY, hit);
        }
        *segs += (uint64_t)n;
        /* the hits, then the misses: two loops over bit masks instead of
         * a branch on hit or miss in every lane */
        for (int m = found; m; m &= m - 1) {
            const int k = __builtin_ctz((unsigned)m);
            if (!path_step(pc, &p[k], 1, &hit[k], depth))
                live &= ~(1 << k);
        }
        for (int m = all & ~found; m; m &= m - 1) {
            const int k = __builtin_ctz((unsigned)m);
            path_step(pc, &p[k], 0, &hit[k], depth);
            live &= ~(1 << k);
        }
    }
    /* The paths still live go on one at a time, each to its end:
     * consecutive segments of a path start where the last one ended, which
     * keeps the traversal's memory and branch history warm better than
     * taking the paths in turn. */
    for (; live; live &= live - 1)
        path_trace(pc, &p[__builtin_ctz((unsigned)live)], depth, segs, NULL, 1);
    for (int k = 0; k < n; k++)
        add_sample(acc, &p[k], pc->aovs);
}
#endif

/* Adds acc, the sums of samples [s0, s) of a pixel, to its values px
 * (r->lay): with adapt, the count of them; with aovs, the buffers. */
static inline void pixel_store(const rt_renderer *r, const pixel_acc *acc, int64_t *px, uint32_t n, int adapt,
                               int aovs)
{
    px[0] += acc->c[0];
    px[1] += acc->c[1];
    px[2] += acc->c[2];
    if (adapt)
        px[r->lay.count] += n;
    if (aovs && r->lay.albedo)
        for (int k = 0; k < 3; k++)
            px[r->lay.albedo + k] += acc->aov[k];
    if (aovs && r->lay.normal)
        for (int k = 0; k < 3; k++)
            px[r->lay.normal + k] += acc->aov[3 + k];
}

/* The samples s0..s1-1 of pixel (x, y) added in fixed point to px (the
 * pixel's values, r->lay); with adaptive sampling only those below the
 * pixel's count (rt_render_pilot), and the count of them. Returns the ray
 * segments traced. avx: paths in packets (pixel_packet). extras: the job
 * may have adaptive sampling or buffers (r->lay.ch > 3); a constant, so
 * that the path loop of a plain job has none of their code (+3.1 %
 * instructions with it). */
static inline __attribute__((always_inline)) uint64_t pixel(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t s0,
                                                            uint32_t s1, int64_t *px, const int avx, const int extras)
{
    pixel_acc acc; /* a local, kept in registers */
    memset(&acc, 0, sizeof acc);
    uint64_t segs = 0;
    const int adapt = extras && r->lay.count != 0;
    const pixel_ctx pc = pixel_start(r, x, y, pixel_key(r, x, y), extras && (r->lay.albedo || r->lay.normal));
    if (adapt) { /* the pixel takes samples [0, its count) */
        const uint32_t n = pilot_count(&pc, &segs);
        s1 = s1 < n ? s1 : n;
        s0 = s0 < s1 ? s0 : s1;
    }
    uint32_t s = s0;
#if RT_BVH_HAVE_AVX
    if (avx)
        for (; s < s1; s += RT_RENDER_PACKET)
            pixel_packet(&pc, s, s1 - s < RT_RENDER_PACKET ? (int)(s1 - s) : RT_RENDER_PACKET, &acc, &segs);
    else
#else
    (void)avx;
#endif
        for (; s < s1; s++) {
            path p;
            path_start(&pc, s, &p);
            path_trace(&pc, &p, 0, &segs, NULL, 0);
            add_sample(&acc, &p, pc.aovs);
        }
    pixel_store(r, &acc, px, s1 - s0, adapt, pc.aovs);
    return segs;
}

#endif
