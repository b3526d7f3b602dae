/* render.h - the render core: traces the samples of a block of rows and adds
 * them, in fixed point, to an accumulation buffer.
 *
 * Why fixed point: a pixel's value is the sum of its samples. Integer
 * addition is associative, so any split of the work (bands, sample ranges,
 * progressive passes, resumed checkpoints, partial sums added on rank 0) adds
 * up to exactly the same bits. Each sample's colour is rounded to 2^-32 - far
 * below what 8- or 16-bit output or a float can show. */
#ifndef RT_RENDER_H
#define RT_RENDER_H

#include <signal.h>
#include <stdint.h>

#include "accel.h"
#include "camera.h"
#include "job.h"
#include "material.h"
#include "sampler.h"
#include "scene.h"
#include "schedule.h"

/* Version of the sampling: which random numbers a sample draws and what it
 * does with them. Bumped whenever a change alters any pixel of any image, so
 * that a checkpoint written by another version is refused instead of mixed
 * in. 2: unit vectors sampled directly (no rejection). 3: the Sobol
 * sampler and Russian roulette by default, the sampler and the roulette
 * chosen by the job (job.h) (the random sampler without roulette draws
 * version 2's numbers). 4: the sampler as an interface of dimensions
 * (sampler.h's table: a bounce's numbers in request order), and Sobol
 * pairs with a shorter index shuffle and digital shifts instead of
 * coordinate scrambles, at a fraction of version 3's cost (the random
 * sampler's numbers unchanged). 5: scenes with emitters sample their
 * lights (nee.h; sampler.h's lit layout), unless --no-light-sampling,
 * whose images, and those of every scene without emitters, keep version
 * 4's bytes. 6: lit scenes' shadow rays under Russian roulette when
 * faint (nee.c), decided by the light choice's number. 7: in lit scenes
 * with glass spheres (book3-final, book2-final), a lambertian vertex aims
 * one in eight of its scattered directions at them (nee.c), from the same
 * 2D number; other lit scenes (cornell-box) keep version 6's bytes. 8:
 * lit scenes with media (book2-final, cornell-smoke) sample the light
 * their thin media scatter along a segment from the camera or a specular
 * vertex (path2.c's inscatter; 14 dimensions a bounce), and a fuzzy
 * metal vertex of a lit scene samples the lights (nee.h, with its
 * scattering's density); other scenes keep version 7's bytes. 9: lit
 * scenes with glass spheres and no media (book3-final) estimate the light
 * the spheres focus onto a lambertian vertex in their shadow through them
 * (caustic.h; 14 dimensions a bounce); other scenes keep version 8's
 * bytes. 10: at surfaces the shadow-ray roulette (nee.c) takes only
 * shadow rays ten times fainter than before (media keep version 9's
 * threshold): lit scenes' bytes change, brute force and scenes without
 * emitters keep version 9's. */
#define RT_RENDER_SAMPLING 10u

/* Russian roulette starts after RT_RENDER_ROULETTE_DEPTH bounces and cuts
 * only paths whose throughput has fallen below RT_RENDER_ROULETTE_KEEP in
 * every channel. Measured on the final, materials and defocus scenes
 * (150x100, 256 spp, Sobol): the classic rule (survival = the throughput's
 * largest channel, KEEP 1) saved 16 % of the ray segments but doubled the
 * mean square error: under a bright sky a path of throughput 0.1 still
 * brings a tenth of a pixel's light. KEEP 1/8 after 3 bounces: MSE x1.007,
 * x1.014, x1.004 for x0.915, x0.926, x0.968 the segments, the best of 2, 3,
 * 5 bounces x 1/4, 1/8, 1/16 (error x segments 8.6 %, 6.5 %, 2.9 % lower). */
#define RT_RENDER_ROULETTE_DEPTH 3u
#define RT_RENDER_ROULETTE_KEEP 0.125
/* Adaptive sampling (--noise-threshold): before its samples, a pixel traces
 * RT_ADAPT_FIRST pilot samples with numbers of their own (its key for the
 * seed XOR RT_ADAPT_PILOT_SALT), which only decide how many samples it
 * takes: the fewest of 16, 32, 64, ... (at most -s) whose mean the pilot's
 * spread says is within the threshold times the mean (RT_ADAPT_FLOOR at
 * least, so that dark pixels are held to an absolute error instead). Its
 * image value is the mean of samples [0, count) of its usual sequence.
 * Why a pilot: a count decided by the samples it averages is biased (a
 * pixel whose paths happened to do well looks brighter and less noisy and
 * stops sooner: +0.36 % on the final scene's mean when the rule looked at
 * the samples themselves at 16, 32, 64, ...); a count decided by numbers
 * independent of them is not. And any rank can compute it, for any
 * sample range of the pixel: the work splits as it does without. The
 * price: every unit that renders a pixel traces its pilot again (a row
 * split into k sample ranges, or k progressive passes, trace it k times).
 * Powers of two are where a Sobol sequence's points are evenly spread. */
#define RT_ADAPT_FIRST 16u
#define RT_ADAPT_FLOOR 0.05
#define RT_ADAPT_PILOT_SALT 0x70696c6f74ull /* "pilot" */

/* The samples a pixel takes: from its pilot's n samples, whose luminance
 * has sum and sum of squares sum2 (n >= 2), the threshold and -s. */
uint32_t rt_render_adapt_count(double sum, double sum2, uint32_t n, double threshold, uint32_t samples);

#define RT_FIX_SHIFT 32
#define RT_FIX_ONE 4294967296.0
/* Per-sample radiance is clamped to this so that sums of up to
 * RT_MAX_SAMPLES samples fit in int64 (1024 * 2^20 * 2^32 = 2^62). */
#define RT_SAMPLE_MAX 1024.0
#define RT_MAX_SAMPLES (1u << 20)

typedef struct rt_renderer {
    const rt_scene *scene;
    const rt_accel *accel;
    rt_camera camera;
    rt_job job;
    /* When set and *stop becomes non-zero (a signal), rendering skips the
     * remaining pixels: rt_render_stream drops the units in hand, and the
     * caller of rt_render_rows discards its block. */
    const volatile sig_atomic_t *stop;
    /* Our BVH when it runs the AVX box test (rt_accel_bvh_avx), else NULL:
     * the renderer then runs its copy of the path loop compiled for AVX,
     * with the AVX traversal inlined. */
    const struct rt_bvh *bvh_avx;
    /* When set, camera rays of the pixels whose tile has a list take their
     * closest hit from it (primary.h) instead of the intersector; the
     * caller builds it for this camera and image size (NULL after
     * rt_render_init). */
    const struct rt_primary *primary;
    rt_layout lay; /* the values of a pixel's sums (job.h) */
    /* The scene's book-2 content (rt_accel_world), or NULL: then the
     * book-2 path loop (path2.c) renders it. */
    const struct rt_world *world;
    /* The book-2 loop's camera-ray lists (rt_world_lists_build), as
     * primary for book 1's: the caller builds them for this camera and
     * image size (NULL after rt_render_init). */
    const struct rt_world_lists *wlists;
    /* The emitters the book-2 path loop samples (rt_accel_lights), or NULL
     * (none, --no-light-sampling, or a diffuse model other than the
     * lambertian one, whose density next-event estimation assumes): then
     * it finds them by chance, as the book-2 loop always has. */
    const struct rt_lights *lights;
    uint32_t light_targets; /* rt_lights_target_count(lights), kept for the path loop's every vertex */
    /* The book-2 path loop's rays have their time in [time0, time1)
     * (time0 + u (time1 - time0)): the frame's shutter (anim.h). */
    double time0, time1;
    /* Tests only: the book-2 loop draws a vertex's scattering numbers after
     * the walk that finds it, not ahead of it (path2.c's look_ahead): the
     * images must be the same bits. 0 after rt_render_init. */
    int no_look_ahead;
    int no_caustic; /* tests, experiments: no next-event estimation through glass spheres (caustic.h) */
    /* The book-2 loop runs in AVX-512 lanes, eight paths at a time
     * (path_lanes.h: scenes of a few quads without light sampling, on CPUs
     * that have it): set by rt_render_init, the same image either way. */
    int lanes;
} rt_renderer;

/* A renderer of s's camera, its rays' time in the book's [0, 1). */
int rt_render_init(rt_renderer *r, const rt_scene *s, const rt_accel *a, const rt_job *job);
/* r renders a frame: camera cam, rays' time in [t0, t1) (rt_anim_frame's);
 * the accelerator must hold the moving spheres at those times
 * (rt_accel_new_span). RT_EINVAL for a degenerate camera or t1 < t0. */
int rt_render_frame(rt_renderer *r, const rt_camera_desc *cam, double t0, double t1);

/* A pixel's count under r's job, from its pilot (whose ray segments are
 * added to *segments). */
uint32_t rt_render_pilot(const rt_renderer *r, uint32_t x, uint32_t y, uint64_t *segments);

/* A source of work units for rt_render_stream. take fills *u with the next
 * unit and returns 1, returns 0 when there are no more (it is not called
 * again then), or -1 when there is none yet (only with a poll, which brings
 * them). done receives each finished unit once: its sums, laid out as
 * rt_render_rows' acc but for columns [u->x0, u->x1) only (row u->y0
 * first) and valid only during the call, and
 * the ray segments it took. Each is called by one thread at a time, from
 * any thread of the team; take may run while done does. poll, when not
 * NULL, is called by the team's master thread only (the thread that called
 * rt_render_stream), after each pixel it renders (it must return quickly
 * when it has nothing to do; idle = 0) and over and over while it has
 * nothing to render: idle = RT_POLL_NONE_YET right after its take said -1
 * (it may sleep a little, or wait until take may have units or wake is
 * called), RT_POLL_BUSY while every unit in hand is being rendered by the
 * other threads. It returns 1 when it may have brought units for take, 0
 * when not, and -1 (when busy) to have the master wait for a unit in hand
 * to be done instead of polling again. wake, when not NULL, is called by
 * each other thread of the team as it leaves the stream (no unit left, a
 * failure, or *r->stop), outside the team's lock: a poll waiting must
 * return then, so that the master sees why. */
enum { RT_POLL_NONE_YET = 1, RT_POLL_BUSY = 2 };
typedef struct rt_render_source {
    int (*take)(void *ctx, rt_unit *u);
    void (*done)(void *ctx, const rt_unit *u, const int64_t *sums, uint64_t segments);
    int (*poll)(void *ctx, int idle);
    void (*wake)(void *ctx);
    /* When not NULL, each unit is rendered by its own renderer (a frame
     * job's frame: its camera and shutter): the renderer of u into *r and
     * the row of *r's image that u->y0 is into *y0, called once per unit
     * by the thread that took it, right after take and under the same
     * lock; a status (non-zero ends the stream with it). Then r of
     * rt_render_stream only says how many values a pixel has and when to
     * stop. */
    int (*renderer)(void *ctx, const rt_unit *u, const rt_renderer **r, uint32_t *y0);
    void *ctx;
} rt_render_source;

/* Renders every unit src has, with nthreads OpenMP threads (0 = the OpenMP
 * default) that share out each unit's pixels in runs. A thread that finds
 * every pixel of the units in hand given out takes the next unit instead of
 * waiting for the others at the unit's end, and the thread that finishes a
 * unit's last run hands its sums to done while the others render on: no
 * barrier, no idle thread and no serial step between units. At most
 * RT_RENDER_STREAM_UNITS units are in hand at once (each with a buffer of its
 * own). When *r->stop becomes non-zero, the units in hand are dropped (done
 * is not called for them) and it returns RT_OK; RT_ENOMEM if a buffer could
 * not be had (the units in hand are dropped). */
int rt_render_stream(const rt_renderer *r, int nthreads, const rt_render_source *src);
#define RT_RENDER_STREAM_UNITS 4

/* Samples of a pixel whose paths the AVX path loop takes together
 * (rt_bvh_closest_packet_avx traces up to 8 rays at once). */
#define RT_RENDER_PACKET 8

/* Whether the segments at depth of a group of n samples go to the BVH as
 * one packet (else one ray at a time): the camera rays of two samples or
 * more, and the later segments of a full group while all its paths live
 * (all_live). The path loop follows this, and bench_accel groups the rays
 * it times by it. */
static inline int rt_render_in_packet(int n, int all_live, uint32_t depth)
{
    return (n == RT_RENDER_PACKET && all_live) || (depth == 0 && n >= 2);
}

/* Fixed-point encoding of one sample's channel value. */
static inline int64_t rt_render_fix(double c)
{
    if (!(c >= 0.0)) /* negative or NaN */
        return 0;
    if (c > RT_SAMPLE_MAX)
        c = RT_SAMPLE_MAX;
    return (int64_t)(c * RT_FIX_ONE + 0.5);
}

#endif
