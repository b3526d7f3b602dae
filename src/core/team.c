/* team.c - the OpenMP team that renders a stream of work units
 * (rt_render_stream): threads share out each unit's pixels in runs, take
 * the next unit instead of waiting at a unit's end, and hand finished
 * units to the source; pthread locks and condition variables between
 * them. */
#include "render.h"

#ifdef _OPENMP
#include <omp.h>
#endif

#include <pthread.h>
#include <string.h>

#include "dispatch.h"
#include "mem.h"
#include "status.h"

static inline int omp_thread(void)
{
#ifdef _OPENMP
    return omp_get_thread_num();
#else
    return 0;
#endif
}

typedef struct stream_unit {
    rt_unit u;
    const rt_renderer *r; /* its renderer (the stream's, or the source's for it) */
    rt_dispatch_fn fn;
    uint32_t y0;          /* u->y0 in r's image */
    int64_t *buf;
    size_t cap;                 /* entries of buf */
    long npix, next, left;      /* pixels: in all, next to give out, not yet rendered */
    uint64_t segments, order;   /* order: when it was taken */
    int held;
} stream_unit;

typedef struct stream {
    const rt_renderer *r;
    const rt_render_source *src;
    rt_dispatch_fn fn;
    int threads, status, exhausted;
    uint64_t taken;
    pthread_mutex_t mu;      /* everything below */
    pthread_cond_t freed;    /* a unit was handed on, or a thread left */
    pthread_mutex_t done_mu; /* src->done one call at a time */
    stream_unit units[RT_RENDER_STREAM_UNITS];
    int n_units;
} stream;

/* Under st->mu: every unit slot is held, and the stream goes on (a slot
 * freed, a failure or the end of the units are broadcast on freed). */
static int every_slot_busy(const stream *st)
{
    for (int k = 0; k < st->n_units; k++)
        if (!st->units[k].held)
            return 0;
    return !st->status && !st->exhausted && !rt_dispatch_stopped(st->r);
}

/* The next run of pixels for the calling thread, under st->mu: from the
 * oldest unit in hand that has pixels left, else from a new unit; waits
 * while every unit is given out and none can be taken. Returns the unit,
 * or NULL when there is nothing more to do. */
static stream_unit *stream_claim(stream *st, int master, long *a, long *b)
{
    for (;;) {
        if (st->status || rt_dispatch_stopped(st->r))
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
            empty->r = st->r;
            empty->fn = st->fn;
            empty->y0 = u.y0;
            if (st->src->renderer) {
                int rs = st->src->renderer(st->src->ctx, &u, &empty->r, &empty->y0);
                if (rs) {
                    st->status = rs;
                    return NULL;
                }
                empty->fn = rt_dispatch_pick(empty->r);
            }
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
             * waits: for a unit (take said none yet: an empty slot), or
             * for a unit in hand to be done (no empty slot) */
            pthread_mutex_unlock(&st->mu);
            int more = st->src->poll(st->src->ctx, empty ? RT_POLL_NONE_YET : RT_POLL_BUSY);
            pthread_mutex_lock(&st->mu);
            if (more > 0)
                pthread_cond_broadcast(&st->freed);
            else if (more < 0 && !empty && every_slot_busy(st))
                pthread_cond_wait(&st->freed, &st->mu);
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
        for (long i = a, next; i < b && !rt_dispatch_stopped(r); i = next) {
            segs += rt_dispatch_block_run(su->r, su->fn, su->u.x0, su->u.x1 - su->u.x0, su->y0, su->u.s0, su->u.s1, i,
                                          b, su->buf, &next);
            /* the master polls after every pixel or run of them (the source
             * decides how often to really look), and so right after a unit
             * is done: its next pixel, or its idle poll in stream_claim */
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
            if (!rt_dispatch_stopped(r)) {
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
    if (!master && st->src->wake)
        st->src->wake(st->src->ctx); /* so may the master, waiting in the source's poll */
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
    st.fn = rt_dispatch_pick(r);
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
