/* worker.c - a rank other than 0. Its units come from rank 0; it reports
 * each one done (a few bytes, which also asks for the next) and keeps the
 * sums (held.h), sending them combined when rank 0 asks, when it holds
 * flush_bytes, at its flush interval, and on a signal. Only the main
 * thread may call MPI (MPI_THREAD_FUNNELED) while any thread of the render
 * stream takes units and hands in results: take and done only move units
 * and sums through this state, under mu; poll, on the main thread (the
 * stream's master, between its pixels), does the MPI. While it has nothing
 * else to say for a quarter of the lease, it sends a beat: rank 0 takes a
 * rank it has not heard from for a lease as lost. */
#include "inbox.h"
#include "internal.h"
#include "msg.h"
#include "policy.h"

#include <math.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "array.h"
#include "clock.h"
#include "status.h"

/* A signal reached this worker (mpirun forwards it to every rank), or rank
 * 0 said STOP: its sums are sent. Rank 0 saves the checkpoint and its exit
 * ends the job; a worker that left first would make mpirun report the
 * worker instead, so it waits to be ended, and leaves by itself only if
 * rank 0 does not (a signal sent to it alone). */
static void worker_stop(void) __attribute__((noreturn));
static void worker_stop(void)
{
    for (int i = 0; i < 100; i++) {
        struct timespec ts = {0, 50000000L};
        nanosleep(&ts, NULL);
    }
    _exit(RT_EXIT_INTERRUPTED);
}

typedef struct in_hand {
    uint32_t id;
    int used;
    double taken;
} in_hand;

typedef struct worker {
    rt_farm *f;
    const rt_farm_job *job;
    rt_rank_stats *me;
    double t_start, last_end, last_poll, last_sent, last_flush;
    double flush_interval, beat;
    size_t flush_bytes;
    pthread_mutex_t mu;
    rt_unit *queue; /* received, not yet taken (a ring of depth) */
    in_hand *hand;  /* taken, not yet done: when each was taken */
    int depth, qhead, qlen, finished, failed, flush_wanted;
    int64_t *reports; /* RT_MSG_REPORT per unit done, not yet reported */
    size_t n_reports, cap_reports;
    rt_held held;      /* sums not yet sent */
    rt_held *sealed;   /* full stores waiting to be sent, oldest first */
    size_t n_sealed, cap_sealed, sealed_bytes;
    double held_peak;  /* bytes */
    atomic_int ready;  /* reports or sums wait (set by done, read by poll without mu) */
    int calls, stride, idle; /* poll: calls since it last read the clock, and every how many it does */
    int64_t *msg;      /* a piece being sent */
    size_t cap_msg;
#ifdef RT_TEST_HOOKS
    long slow_ms; /* RT_TEST_SLOW_RANK: this rank sleeps so long after each unit */
#endif
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

/* A unit that shares rows with the store without extending it starts a new
 * store; the full one waits to be sent. Under mu. */
static int seal(worker *w)
{
    if (rt_array_reserve((void **)&w->sealed, &w->cap_sealed, w->n_sealed + 1, sizeof *w->sealed))
        return RT_ENOMEM;
    w->sealed[w->n_sealed++] = w->held;
    w->sealed_bytes += w->held.bytes;
    rt_held_init(&w->held, w->held.width, w->held.ch);
    return RT_OK;
}

/* A finished unit: its report queued, its sums added to the store. done
 * calls come one at a time (rt_render_stream). */
static void worker_done(void *ctx, const rt_unit *u, const int64_t *sums, uint64_t segs)
{
    worker *w = ctx;
#ifdef RT_TEST_HOOKS
    if (w->slow_ms > 0) {
        struct timespec ts = {w->slow_ms / 1000, (w->slow_ms % 1000) * 1000000L};
        nanosleep(&ts, NULL);
    }
#endif
    double end = rt_now() - w->t_start, taken = 0;
    pthread_mutex_lock(&w->mu);
    for (int k = 0; k < w->depth; k++)
        if (w->hand[k].used && w->hand[k].id == u->id) {
            taken = w->hand[k].taken;
            w->hand[k].used = 0;
            break;
        }
    const double start = rt_farm_unit_start(taken, &w->last_end, end);
    int st = rt_array_reserve((void **)&w->reports, &w->cap_reports, w->n_reports + RT_MSG_REPORT, sizeof(int64_t));
    if (!st && !rt_held_fits(&w->held, u))
        st = seal(w);
    if (!st)
        st = rt_held_add(&w->held, u, sums);
    if (st) {
        w->failed = 1; /* poll ends the job: only the main thread may */
    } else {
        const rt_msg_report rep = {.id = u->id, .segs = segs, .start = start, .end = end};
        rt_msg_report_encode(w->reports + w->n_reports, &rep);
        w->n_reports += RT_MSG_REPORT;
        double held = (double)(w->held.bytes + w->sealed_bytes);
        if (held > w->held_peak)
            w->held_peak = held;
        if (w->held.bytes + w->sealed_bytes >= w->flush_bytes)
            w->flush_wanted = 1;
    }
    atomic_store(&w->ready, 1);
    pthread_mutex_unlock(&w->mu);
    rt_rank_stats_add(w->me, u, w->job->renderer->job.width, w->job->renderer->job.samples, segs, start, end);
}

static void send_or_fail(worker *w, const void *buf, int count, MPI_Datatype type, int tag)
{
    if (MPI_Send(buf, count, type, 0, tag, MPI_COMM_WORLD) != MPI_SUCCESS)
        rt_farm_fail(w->f, RT_EXIT_RUNTIME, "cannot reach rank 0");
    w->last_sent = rt_now();
}

static void send_reports(worker *w)
{
    pthread_mutex_lock(&w->mu);
    if (w->failed)
        rt_farm_fail(w->f, RT_EXIT_RUNTIME, "out of memory for the sums of a unit");
    int64_t *r = w->reports;
    size_t n = w->n_reports;
    w->reports = NULL;
    w->n_reports = w->cap_reports = 0;
    pthread_mutex_unlock(&w->mu);
    if (n)
        send_or_fail(w, r, (int)n, MPI_INT64_T, RT_TAG_REPORT);
    free(r);
}

/* One message for the pieces of a store: each row at most once. */
static void send_pieces(worker *w, const rt_piece *p, size_t n_pieces)
{
    if (!n_pieces)
        return;
    const size_t ch = w->held.ch;
    size_t n = 0;
    for (size_t i = 0; i < n_pieces; i++)
        n += rt_msg_piece_len(&p[i], ch);
    if (rt_array_reserve((void **)&w->msg, &w->cap_msg, n, sizeof *w->msg))
        rt_farm_fail(w->f, RT_EXIT_RUNTIME, "out of memory for the sums to send");
    int64_t *m = w->msg;
    for (size_t i = 0; i < n_pieces; i++)
        m = rt_msg_piece_encode(m, &p[i], ch);
    send_or_fail(w, w->msg, (int)n, MPI_INT64_T, RT_TAG_SUMS);
}

/* Sends every sum held: the sealed stores first, then the current one.
 * The reports go first, so rank 0 knows each unit done before its sums. */
static void flush(worker *w)
{
    send_reports(w);
    pthread_mutex_lock(&w->mu);
    rt_held *sealed = w->sealed;
    size_t n_sealed = w->n_sealed, n_cur;
    rt_piece *cur = rt_held_take(&w->held, &n_cur);
    w->sealed = NULL;
    w->n_sealed = w->cap_sealed = w->sealed_bytes = 0;
    w->flush_wanted = 0;
    pthread_mutex_unlock(&w->mu);
    for (size_t i = 0; i < n_sealed; i++) {
        send_pieces(w, sealed[i].pieces, sealed[i].n);
        rt_held_free(&sealed[i]);
    }
    free(sealed);
    send_pieces(w, cur, n_cur);
    rt_held_free_pieces(cur, n_cur);
    w->last_flush = rt_now();
}

/* Units from rank 0, into the ring. */
static void receive_units(worker *w, const MPI_Status *status)
{
    int count = 0;
    MPI_Get_count(status, MPI_UINT32_T, &count);
    uint32_t *m = count > 0 ? malloc((size_t)count * sizeof *m) : NULL;
    rt_unit *units = count > 0 ? malloc(((size_t)count / RT_MSG_UNIT + 1) * sizeof *units) : NULL;
    if (count <= 0 || count % RT_MSG_UNIT || !m || !units)
        rt_farm_fail(w->f, RT_EXIT_RUNTIME, "malformed units from rank 0");
    MPI_Recv(m, count, MPI_UINT32_T, 0, RT_TAG_UNITS, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    const rt_job *j = &w->job->renderer->job;
    const uint64_t rows = (uint64_t)j->height * (w->job->frames ? w->job->frames : 1); /* a frame job's: all frames' */
    size_t n = 0;
    pthread_mutex_lock(&w->mu);
    int bad = rt_msg_units_decode(m, (size_t)count, units, (size_t)(w->depth - w->qlen), &n) != RT_OK;
    for (size_t k = 0; k < n && !bad; k++) {
        const rt_unit u = units[k];
        bad |= u.y1 <= u.y0 || u.y1 > rows || u.x1 <= u.x0 || u.x1 > j->width || u.s1 <= u.s0 ||
               u.s1 > j->samples;
        if (!bad)
            w->queue[(w->qhead + w->qlen++) % w->depth] = u;
    }
    pthread_mutex_unlock(&w->mu);
    free(m);
    free(units);
    if (bad)
        rt_farm_fail(w->f, RT_EXIT_RUNTIME, "malformed or unrequested units from rank 0");
}

/* Everything rank 0 sent; returns 1 when something came. */
static int receive(worker *w)
{
    int got = 0;
    for (;;) {
        int flag = 0;
        MPI_Status status;
        if (rt_inbox_probe(0, &flag, &status) != MPI_SUCCESS)
            rt_farm_fail(w->f, RT_EXIT_RUNTIME, "MPI_Iprobe failed");
        if (!flag)
            return got;
        got = 1;
        int tag = status.MPI_TAG;
        if (tag == RT_TAG_UNITS) {
            receive_units(w, &status);
            continue;
        }
        if (tag == RT_TAG_FINISH) {
            int32_t lost = 0;
            MPI_Recv(&lost, 1, MPI_INT32_T, 0, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            w->f->lost = lost;
            pthread_mutex_lock(&w->mu);
            w->finished = 1;
            pthread_mutex_unlock(&w->mu);
            continue;
        }
        MPI_Recv(NULL, 0, MPI_BYTE, 0, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        pthread_mutex_lock(&w->mu);
        if (tag == RT_TAG_IDLE || tag == RT_TAG_FLUSH)
            w->flush_wanted = 1;
        pthread_mutex_unlock(&w->mu);
        if (tag == RT_TAG_STOP)
            rt_farm_stop_raise(SIGTERM);
        else if (tag != RT_TAG_IDLE && tag != RT_TAG_FLUSH)
            rt_farm_fail(w->f, RT_EXIT_RUNTIME, "unexpected message tag %d from rank 0", tag);
    }
}

/* Stopped by a signal or by rank 0: the sums go out, then it waits to be
 * ended. */
static void stop(worker *w)
{
    flush(w);
    send_or_fail(w, NULL, 0, MPI_BYTE, RT_TAG_STOPPED);
    worker_stop();
}

/* The stream's poll, after every pixel of the master thread: the worker's
 * MPI, on its main thread. Reports go out at once; otherwise, while
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
    atomic_store(&w->ready, 0);
    if (RT_FARM_STOPPED())
        stop(w);
    pthread_mutex_lock(&w->mu);
    int due = w->flush_wanted || w->n_sealed ||
              ((w->held.n || w->n_reports) && t0 - w->last_flush >= w->flush_interval);
    pthread_mutex_unlock(&w->mu);
    if (due)
        flush(w);
    else
        send_reports(w);
    if (t0 - w->last_sent > w->beat)
        send_or_fail(w, NULL, 0, MPI_BYTE, RT_TAG_BEAT);
    int got = receive(w);
    if (RT_FARM_STOPPED())
        stop(w); /* the stream would drop its units and end: stop here */
    if (got)
        w->idle = 0;
    if (idle && !got) {
        rt_inbox_nap(&w->idle);
        w->me->wait += rt_now() - t0;
    } else {
        w->me->comm += rt_now() - t0;
    }
    return got;
}

void rt_farm_work(rt_farm *f, const rt_farm_job *job, rt_rank_stats *me, double t_start)
{
    worker w;
    memset(&w, 0, sizeof w);
    w.f = f;
    w.job = job;
    w.me = me;
    w.t_start = t_start;
    w.depth = job->prefetch > 0 ? job->prefetch : RT_POLICY_PREFETCH;
    w.stride = 1;
    /* never on a timer: an interval no wait reaches */
    w.flush_interval = job->flush_interval == RT_POLICY_FLUSH_NEVER ? INFINITY : job->flush_interval;
    w.flush_bytes = job->flush_bytes > 0 ? job->flush_bytes : (size_t)RT_POLICY_FLUSH_MB << 20;
    w.beat = (job->lease > 0 ? job->lease : RT_POLICY_LEASE) / 4.0;
    w.last_flush = w.last_sent = rt_now();
    /* The first flush comes after a share of the interval that grows with
     * the rank, so that the workers' flushes reach rank 0 spread over each
     * interval, not all at once (by the model, 0.905 -> 0.938 for the
     * default job at 64 x 16, docs/SCALING.md). */
    if (f->size > 2 && isfinite(w.flush_interval))
        w.last_flush -= w.flush_interval * (f->rank - 1) / (f->size - 1);
    atomic_init(&w.ready, 0);
    rt_held_init(&w.held, job->renderer->job.width, job->renderer->lay.ch);
    w.queue = malloc((size_t)w.depth * sizeof *w.queue);
    w.hand = calloc((size_t)w.depth, sizeof *w.hand);
    if (!w.queue || !w.hand)
        rt_farm_fail(f, RT_EXIT_RUNTIME, "out of memory for work buffers");
    pthread_mutex_init(&w.mu, NULL);
#ifdef RT_TEST_HOOKS
    /* Test builds only: make one rank fail, to check that the job ends
     * promptly (tests/e2e/e2e_determinism.sh). */
    const char *fault = getenv("RT_FAULT_INJECT_RANK");
    if (fault && atoi(fault) == f->rank)
        rt_farm_fail(f, RT_EXIT_RUNTIME, "fault injected for testing (RT_FAULT_INJECT_RANK=%s)", fault);
    /* ... or one rank slow: RT_TEST_SLOW_RANK=rank:ms after each unit */
    const char *slow = getenv("RT_TEST_SLOW_RANK");
    if (slow && atoi(slow) == f->rank && strchr(slow, ':'))
        w.slow_ms = atol(strchr(slow, ':') + 1);
#endif
    char host[sizeof me->host];
    rt_sysinfo_hostname(host, sizeof host);
    send_or_fail(&w, host, (int)strlen(host), MPI_BYTE, RT_TAG_HOST);
    int32_t want = w.depth;
    send_or_fail(&w, &want, 1, MPI_INT32_T, RT_TAG_HELLO);
    rt_render_source src = {.take = worker_take, .done = worker_done, .poll = worker_poll, .ctx = &w};
    int st = rt_farm_run_units(job, &src);
    if (st)
        rt_farm_fail(f, RT_EXIT_RUNTIME, "rendering failed: %s", rt_status_str(st));
    if (RT_FARM_STOPPED())
        stop(&w);
    /* FINISH came: every sum is in, this flush sends nothing. */
    flush(&w);
    const rt_msg_bye b = {me->wait, me->comm, rt_sysinfo_peak_mb(), w.held_peak / (1024.0 * 1024.0)};
    double bye[RT_MSG_BYE];
    rt_msg_bye_encode(bye, &b);
    send_or_fail(&w, bye, RT_MSG_BYE, MPI_DOUBLE, RT_TAG_BYE);
    rt_held_free(&w.held);
    free(w.reports);
    free(w.msg);
    free(w.queue);
    free(w.hand);
    pthread_mutex_destroy(&w.mu);
}
