/* units.c - running a rank's units, on rank 0 and on workers alike:
 * rendered (rt_render_stream), or the empty units of the farm benchmark;
 * and the per-unit time accounting both share. */
#include "internal.h"

#include <stdlib.h>

#include "status.h"

/* A frame job's ring of frame renderers on this rank: slot k % RT_FARM_RING
 * holds frame index k's, built (job->frame_renderer) by the thread that
 * takes the first unit of k that the slot sees, under the stream's lock:
 * the other threads go on rendering their runs meanwhile, and wait only if
 * they need a new run before it is built (once per frame and rank: the
 * camera, shutter and camera-ray lists that the frame-by-frame job set up
 * before each frame on every rank). The slot must hold no
 * unit in hand then: the cap guarantees it (a unit of frame k is handed
 * out only when every frame before k - cap + 1 is complete, so every unit
 * of frame k - RT_FARM_RING is done on every rank), and a slot still in use
 * is an error (RT_EINVAL), never a silent rebuild under a unit. */
typedef struct ring {
    const rt_farm_job *job;
    const rt_render_source *src; /* the rank's source */
    pthread_mutex_t mu;          /* the slots: take and done run under different locks */
    struct {
        const rt_renderer *r;
        uint32_t index, in_hand; /* the frame it holds, its units in hand */
        int built;
    } slot[RT_FARM_RING];
} ring;

static int ring_take(void *ctx, rt_unit *u)
{
    const ring *g = ctx;
    return g->src->take(g->src->ctx, u);
}

static int ring_poll(void *ctx, int idle)
{
    const ring *g = ctx;
    return g->src->poll(g->src->ctx, idle);
}

static void ring_wake(void *ctx)
{
    const ring *g = ctx;
    g->src->wake(g->src->ctx);
}

static uint32_t frame_of(const ring *g, const rt_unit *u) { return u->y0 / g->job->renderer->job.height; }

static int ring_renderer(void *ctx, const rt_unit *u, const rt_renderer **r, uint32_t *y0)
{
    ring *g = ctx;
    const uint32_t k = frame_of(g, u), i = k % RT_FARM_RING;
    int st = RT_OK;
    pthread_mutex_lock(&g->mu);
    if (!g->slot[i].built || g->slot[i].index != k) {
        if (g->slot[i].in_hand) {
            st = RT_EINVAL; /* frame index - RT_FARM_RING still in hand: the cap was broken */
        } else {
            g->slot[i].built = 0;
            g->slot[i].index = k;
            st = g->job->frame_renderer(g->job->frame_ctx, i, k, &g->slot[i].r);
            g->slot[i].built = !st;
        }
    }
    if (!st) {
        g->slot[i].in_hand++;
        *r = g->slot[i].r;
        *y0 = u->y0 - k * g->job->renderer->job.height;
    }
    pthread_mutex_unlock(&g->mu);
    return st;
}

static void ring_done(void *ctx, const rt_unit *u, const int64_t *sums, uint64_t segments)
{
    ring *g = ctx;
    g->src->done(g->src->ctx, u, sums, segments);
    pthread_mutex_lock(&g->mu);
    g->slot[frame_of(g, u) % RT_FARM_RING].in_hand--;
    pthread_mutex_unlock(&g->mu);
}

int rt_farm_run_units(const rt_farm_job *job, const rt_render_source *src)
{
    if (!job->empty_units && job->frames) {
        ring g = {.job = job, .src = src};
        pthread_mutex_init(&g.mu, NULL);
        const rt_render_source rs = {.take = ring_take,
                                     .done = ring_done,
                                     .poll = src->poll ? ring_poll : NULL,
                                     .wake = src->wake ? ring_wake : NULL,
                                     .renderer = ring_renderer,
                                     .ctx = &g};
        int st = rt_render_stream(job->renderer, job->threads, &rs);
        pthread_mutex_destroy(&g.mu);
        return st;
    }
    if (!job->empty_units)
        return rt_render_stream(job->renderer, job->threads, src);
    /* --empty-units: every unit adds nothing, without rendering; the zero
     * sums come from one buffer that grows to the largest unit. */
    const size_t ch = job->renderer->lay.ch;
    int64_t *zero = NULL;
    size_t cap = 0;
    int st = RT_OK, got;
    rt_unit u;
    while (!RT_FARM_STOPPED() && (got = src->take(src->ctx, &u)) != 0) {
        if (got > 0) {
            size_t n = (size_t)rt_unit_pixels(&u) * ch;
            if (n > cap) {
                free(zero);
                cap = 0;
                if (!(zero = calloc(n, sizeof *zero))) {
                    st = RT_ENOMEM;
                    break;
                }
                cap = n;
            }
            src->done(src->ctx, &u, zero, 0);
        }
        if (src->poll)
            src->poll(src->ctx, got < 0);
    }
    free(zero);
    return st;
}

double rt_farm_unit_start(double taken, double *last, double end)
{
    double start = taken > *last ? taken : *last;
    *last = end;
    return start;
}
