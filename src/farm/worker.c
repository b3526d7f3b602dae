/* worker.c - a rank other than 0. Its units come from rank 0 and its
 * results go back by MPI, which only its main thread may call
 * (MPI_THREAD_FUNNELED), while any thread of the render stream takes units
 * and hands in results. So the stream's take and done only move units and
 * results through this state, under mu; poll, on the main thread (the
 * stream's master, between its pixels), does the MPI: it posts the results
 * ready, completes sends, and receives units. It asks for `prefetch` units
 * up front, so the next unit is always at hand. */
#include "msg.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "array.h"
#include "clock.h"
#include "status.h"

/* A signal reached this worker (mpirun forwards it to every rank). Rank 0
 * saves the checkpoint and its exit ends the job; a worker that left first
 * would make mpirun report the worker instead, so it waits to be ended, and
 * leaves by itself only if rank 0 does not (a signal sent to it alone). */
static void worker_stop(void) __attribute__((noreturn));
static void worker_stop(void)
{
    for (int i = 0; i < 100; i++) {
        struct timespec ts = {0, 50000000L};
        nanosleep(&ts, NULL);
    }
    _exit(RT_EXIT_INTERRUPTED);
}

/* A result buffer's life: free, being filled by done (outside the lock),
 * ready for poll to send, being sent. */
enum { RES_FREE, RES_FILLING, RES_READY, RES_SENDING };

typedef struct result {
    int64_t *buf; /* RT_MSG_HDR + sums */
    size_t cap, len;
    MPI_Request req;
    int state;
} result;

typedef struct in_hand {
    uint32_t id;
    int used;
    double taken;
} in_hand;

typedef struct worker {
    const rt_farm *f;
    const rt_farm_job *job;
    rt_rank_stats *me;
    double t_start, last_end, last_poll;
    pthread_mutex_t mu;
    rt_unit *queue; /* received, not yet taken */
    in_hand *hand;  /* taken, not yet done: when each was taken */
    int depth, qhead, qlen, finished, idle, failed;
    atomic_int ready; /* a result waits to be sent (set by done, read by poll without mu) */
    int calls, stride; /* poll: calls since it last read the clock, and every how many it does */
    result *res;
    size_t n_res, cap_res;
} worker;

static int worker_take(void *ctx, rt_unit *u)
{
    worker *w = ctx;
    pthread_mutex_lock(&w->mu);
    int got = w->qlen > 0 ? 1 : w->finished ? 0 : -1;
    if (got > 0) {
        *u = w->queue[w->qhead];
        w->qhead = (w->qhead + 1) % w->depth;
        w->qlen--;
        for (int k = 0; k < w->depth; k++)
            if (!w->hand[k].used) { /* there are never more than depth units out */
                w->hand[k] = (in_hand){u->id, 1, rt_now() - w->t_start};
                break;
            }
    }
    pthread_mutex_unlock(&w->mu);
    return got;
}

/* A finished unit: copied into a free result buffer (the stream reuses its
 * own at once, and MPI_Isend needs the data until the send completes),
 * ready for poll to send. The slot is chosen under mu and marked filling, so
 * poll leaves it alone while the copy (and a first malloc's page faults)
 * runs outside the lock, which poll and worker_take need, and the stream's
 * take waits on (the copy under mu held it 14 us a unit: 1.8 ms of a 78 ms
 * render of 600x400 at 2 spp on a worker with two threads; out of it, 1.004
 * and 1.009 in paired rounds, within noise). done calls come one at a
 * time (rt_render_stream), so no other call moves w->res meanwhile. */
static void worker_done(void *ctx, const rt_unit *u, const int64_t *sums, uint64_t segs)
{
    worker *w = ctx;
    const size_t n = RT_MSG_HDR + (size_t)(u->y1 - u->y0) * w->job->renderer->job.width * 3;
    double end = rt_now() - w->t_start, taken = 0;
    pthread_mutex_lock(&w->mu);
    for (int k = 0; k < w->depth; k++)
        if (w->hand[k].used && w->hand[k].id == u->id) {
            taken = w->hand[k].taken;
            w->hand[k].used = 0;
            break;
        }
    const double start = rt_farm_unit_start(taken, &w->last_end, end);
    result *r = NULL;
    for (size_t k = 0; k < w->n_res && !r; k++)
        if (w->res[k].state == RES_FREE)
            r = &w->res[k];
    if (!r && rt_array_reserve((void **)&w->res, &w->cap_res, w->n_res + 1, sizeof *w->res) == RT_OK) {
        r = &w->res[w->n_res++];
        *r = (result){NULL, 0, 0, MPI_REQUEST_NULL, RES_FREE};
    }
    if (!r) {
        w->failed = 1; /* poll ends the job: only the main thread may */
        pthread_mutex_unlock(&w->mu);
        return;
    }
    r->state = RES_FILLING;
    pthread_mutex_unlock(&w->mu);
    if (n > r->cap) {
        free(r->buf);
        r->cap = 0;
        if ((r->buf = malloc(n * sizeof *r->buf)))
            r->cap = n;
    }
    if (r->buf) {
        r->buf[0] = u->id;
        r->buf[1] = (int64_t)segs;
        r->buf[2] = (int64_t)(start * 1e9);
        r->buf[3] = (int64_t)(end * 1e9);
        memcpy(r->buf + RT_MSG_HDR, sums, (n - RT_MSG_HDR) * sizeof *sums);
        r->len = n;
    }
    pthread_mutex_lock(&w->mu);
    if (r->buf) {
        r->state = RES_READY;
        atomic_store(&w->ready, 1);
    } else {
        r->state = RES_FREE;
        w->failed = 1;
    }
    pthread_mutex_unlock(&w->mu);
    rt_rank_stats_add(w->me, u, w->job->renderer->job.samples, segs, start, end);
}

/* Sends the results that are ready and completes the sends that are done;
 * returns 1 when every result ready or sending has gone out (one still
 * being filled is not counted: the final drain runs after the stream has
 * ended, when none is). Main thread only. */
static int worker_send(worker *w)
{
    pthread_mutex_lock(&w->mu);
    if (w->failed)
        rt_farm_fail(w->f, 1, "out of memory for a result");
    int all = 1;
    for (size_t k = 0; k < w->n_res; k++) {
        result *r = &w->res[k];
        if (r->state == RES_READY) {
            if (MPI_Isend(r->buf, (int)r->len, MPI_INT64_T, 0, RT_TAG_RESULT, MPI_COMM_WORLD, &r->req) != MPI_SUCCESS)
                rt_farm_fail(w->f, 1, "sending a result to rank 0 failed");
            r->state = RES_SENDING;
        }
        if (r->state == RES_SENDING) {
            int flag = 0;
            MPI_Test(&r->req, &flag, MPI_STATUS_IGNORE);
            if (flag)
                r->state = RES_FREE;
            else
                all = 0;
        }
    }
    atomic_store(&w->ready, 0);
    pthread_mutex_unlock(&w->mu);
    return all;
}

/* The stream's poll, after every pixel of the master thread: the worker's
 * MPI, on its main thread. Results go out at once; otherwise, while
 * rendering, it looks for messages about every 100 us. Reading the clock
 * costs about 30 ns here, and a pixel at 1 spp about 200 ns, so it reads it
 * only every w->stride calls, the stride doubled or halved to keep the
 * reads 50 to 200 us apart. Idle, it sleeps (nap) when nothing came. */
static int worker_poll(void *ctx, int idle)
{
    worker *w = ctx;
    if (!idle && !atomic_load(&w->ready) && ++w->calls < w->stride)
        return 0;
    w->calls = 0;
    double t0 = rt_now();
    if (!idle && !atomic_load(&w->ready)) {
        double since = t0 - w->last_poll;
        if (since < 50e-6 && w->stride < (1 << 16))
            w->stride *= 2;
        else if (since > 200e-6 && w->stride > 1)
            w->stride /= 2;
        if (since < 1e-4)
            return 0;
    }
    w->last_poll = t0;
    worker_send(w);
    int got = 0;
    for (;;) {
        if (RT_FARM_STOPPED())
            return 1; /* the stream sees the stop too; wake its threads */
        int flag = 0;
        MPI_Status status;
        if (rt_msg_probe(0, &flag, &status) != MPI_SUCCESS)
            rt_farm_fail(w->f, 1, "MPI_Iprobe failed");
        if (!flag)
            break;
        got = 1;
        if (status.MPI_TAG == RT_TAG_UNIT) {
            uint32_t m[5];
            MPI_Recv(m, 5, MPI_UINT32_T, 0, RT_TAG_UNIT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            rt_unit u = {m[0], m[1], m[2], m[3], m[4]};
            const rt_job *p = &w->job->renderer->job;
            if (u.y1 <= u.y0 || u.y1 > p->height || u.s1 <= u.s0 || u.s1 > p->samples)
                rt_farm_fail(w->f, 1, "malformed work unit from rank 0");
            pthread_mutex_lock(&w->mu);
            int full = w->qlen == w->depth;
            if (!full)
                w->queue[(w->qhead + w->qlen++) % w->depth] = u;
            pthread_mutex_unlock(&w->mu);
            if (full)
                rt_farm_fail(w->f, 1, "received more units than requested");
        } else if (status.MPI_TAG == RT_TAG_DONE) {
            MPI_Recv(NULL, 0, MPI_UINT32_T, 0, RT_TAG_DONE, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            pthread_mutex_lock(&w->mu);
            w->finished = 1;
            pthread_mutex_unlock(&w->mu);
        } else {
            rt_farm_fail(w->f, 1, "unexpected message tag %d from rank 0", status.MPI_TAG);
        }
    }
    if (got)
        w->idle = 0;
    if (idle && !got) {
        rt_msg_nap(&w->idle);
        w->me->wait += rt_now() - t0;
    } else {
        w->me->comm += rt_now() - t0;
    }
    return got;
}

void rt_farm_work(const rt_farm *f, const rt_farm_job *job, rt_rank_stats *me, double t_start)
{
    worker w;
    memset(&w, 0, sizeof w);
    w.f = f;
    w.job = job;
    w.me = me;
    w.t_start = t_start;
    w.depth = job->prefetch > 0 ? job->prefetch : 2;
    w.stride = 1;
    atomic_init(&w.ready, 0);
    w.queue = malloc((size_t)w.depth * sizeof *w.queue);
    w.hand = calloc((size_t)w.depth, sizeof *w.hand);
    if (!w.queue || !w.hand)
        rt_farm_fail(f, 1, "out of memory for work buffers");
    pthread_mutex_init(&w.mu, NULL);
#ifdef RT_TEST_HOOKS
    /* Test builds only: make one rank fail, to check that the job ends
     * promptly (tests/e2e/e2e_determinism.sh). */
    const char *fault = getenv("RT_FAULT_INJECT_RANK");
    if (fault && atoi(fault) == f->rank)
        rt_farm_fail(f, 1, "fault injected for testing (RT_FAULT_INJECT_RANK=%s)", fault);
#endif
    int32_t want = w.depth;
    if (MPI_Send(&want, 1, MPI_INT32_T, 0, RT_TAG_HELLO, MPI_COMM_WORLD) != MPI_SUCCESS)
        rt_farm_fail(f, 1, "cannot reach rank 0");
    rt_render_source src = {worker_take, worker_done, worker_poll, &w};
    int st = rt_farm_run_units(job, &src);
    if (st)
        rt_farm_fail(f, 1, "rendering failed: %s", rt_status_str(st));
    if (RT_FARM_STOPPED())
        worker_stop();
    /* The last results out, without spinning. */
    while (!worker_send(&w))
        rt_msg_nap(&w.idle);
    for (size_t k = 0; k < w.n_res; k++)
        free(w.res[k].buf);
    free(w.res);
    free(w.queue);
    free(w.hand);
    pthread_mutex_destroy(&w.mu);
}
