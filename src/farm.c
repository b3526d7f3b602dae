/* farm.c - dynamic distribution of row bands over MPI ranks.
 *
 * Rank 0: the main thread is the server. It never blocks in MPI (Open MPI
 * busy-polls inside blocking calls); it probes and sleeps with a short
 * back-off, so it costs next to no CPU. A second thread renders bands on
 * rank 0 with the job's OpenMP threads, taking them from the same queue the
 * server hands out from. Only the main thread calls MPI (MPI_THREAD_FUNNELED).
 *
 * Workers: ask for `prefetch` units up front; each result they send is also
 * the request for one more unit, so a worker always has the next band at
 * hand and a slow rank simply gets fewer bands. While the OpenMP team renders,
 * the master thread polls its outstanding sends so results flow without
 * waiting for the band to end.
 *
 * Results are fixed-point sums (see render.h), so the order in which they
 * arrive does not change a single bit of the image. */
#define _GNU_SOURCE
#include "farm.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#ifdef RT_HAVE_MPI
#include <mpi.h>
#endif

#include "status.h"

enum { TAG_HELLO = 11, TAG_UNIT = 12, TAG_DONE = 13, TAG_RESULT = 14 };
#define HDR 4 /* result header: unit id, segments, busy ns, rows */

typedef struct unit {
    uint32_t id, y0, y1, s0, s1;
} unit;

typedef struct shared {
    pthread_mutex_t mu;
    const rt_farm_job *job;
    uint32_t W, H, band, samples, nunits, next, done_units;
    uint64_t rows_done, segments;
    int64_t *acc;
    rt_rank_stats *stats;
    int serial; /* no server: the render loop reports progress itself */
    int error;
} shared;

/* ---- set-up ------------------------------------------------------------ */

int rt_farm_init(rt_farm *f, int *argc, char ***argv)
{
    memset(f, 0, sizeof *f);
    f->size = f->local_size = 1;
#ifdef RT_HAVE_MPI
    int provided = 0;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
        return RT_EIO;
    f->mpi = 1;
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &f->rank);
    MPI_Comm_size(MPI_COMM_WORLD, &f->size);
    MPI_Comm node;
    if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, f->rank, MPI_INFO_NULL, &node) == MPI_SUCCESS) {
        MPI_Comm_rank(node, &f->local_rank);
        MPI_Comm_size(node, &f->local_size);
        MPI_Comm_free(&node);
    }
    if (provided < MPI_THREAD_FUNNELED) {
        /* Only the main thread ever calls MPI, but with a lower level we
         * must not even run a second thread on rank 0. */
        if (f->size > 1)
            rt_farm_fail(f, 1, "MPI library provides no MPI_THREAD_FUNNELED support");
    }
#else
    (void)argc;
    (void)argv;
#endif
    return RT_OK;
}

void rt_farm_finalize(rt_farm *f)
{
#ifdef RT_HAVE_MPI
    if (f->mpi)
        MPI_Finalize();
#endif
    f->mpi = 0;
}

void rt_farm_fail(const rt_farm *f, int code, const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (f->size > 1)
        fprintf(stderr, "rt-mpi: error: rank %d: %s\n", f->rank, msg);
    else
        fprintf(stderr, "rt-mpi: error: %s\n", msg);
    fflush(stderr);
#ifdef RT_HAVE_MPI
    if (f->mpi && f->size > 1)
        MPI_Abort(MPI_COMM_WORLD, code);
    if (f->mpi)
        MPI_Finalize();
#endif
    exit(code);
}

void rt_farm_bcast_int(const rt_farm *f, int *v)
{
#ifdef RT_HAVE_MPI
    if (f->mpi && f->size > 1 && MPI_Bcast(v, 1, MPI_INT, 0, MPI_COMM_WORLD) != MPI_SUCCESS)
        rt_farm_fail(f, 1, "MPI_Bcast failed");
#else
    (void)f;
    (void)v;
#endif
}

int rt_farm_bcast_bytes(const rt_farm *f, uint8_t **buf, size_t *len)
{
#ifdef RT_HAVE_MPI
    if (!f->mpi || f->size == 1)
        return RT_OK;
    unsigned long long n = f->rank == 0 ? (unsigned long long)*len : 0;
    if (MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD) != MPI_SUCCESS)
        rt_farm_fail(f, 1, "MPI_Bcast failed");
    if (n > (unsigned long long)INT32_MAX)
        rt_farm_fail(f, 1, "scene of %llu bytes is too large to broadcast", n);
    if (f->rank != 0) {
        *buf = malloc(n ? n : 1);
        if (!*buf)
            rt_farm_fail(f, 1, "out of memory for the %llu-byte scene", n);
        *len = (size_t)n;
    }
    if (MPI_Bcast(*buf, (int)n, MPI_BYTE, 0, MPI_COMM_WORLD) != MPI_SUCCESS)
        rt_farm_fail(f, 1, "MPI_Bcast of the scene failed");
#else
    (void)f;
    (void)buf;
    (void)len;
#endif
    return RT_OK;
}

int rt_farm_default_threads(const rt_farm *f)
{
    cpu_set_t set;
    int n = 0;
    if (sched_getaffinity(0, sizeof set, &set) == 0)
        n = CPU_COUNT(&set);
    long online = sysconf(_SC_NPROCESSORS_ONLN);
    if (n <= 0)
        n = online > 0 ? (int)online : 1;
    /* Unbound ranks that share a node would each see every core. */
    if (f->local_size > 1 && online > 0 && n >= online) {
        int share = (int)online / f->local_size;
        int extra = (int)online % f->local_size;
        n = share + (f->local_rank < extra ? 1 : 0);
    }
    return n > 0 ? n : 1;
}

/* ---- shared queue (rank 0) -------------------------------------------- */

static unit unit_of(const shared *S, uint32_t id)
{
    unit u;
    u.id = id;
    u.y0 = id * S->band;
    u.y1 = u.y0 + S->band < S->H ? u.y0 + S->band : S->H;
    u.s0 = 0;
    u.s1 = S->samples;
    return u;
}

static int take_unit(shared *S, unit *u)
{
    pthread_mutex_lock(&S->mu);
    int ok = S->next < S->nunits;
    if (ok)
        *u = unit_of(S, S->next++);
    pthread_mutex_unlock(&S->mu);
    return ok;
}

static void add_result(shared *S, int rank, const unit *u, const int64_t *sums, uint64_t segs, double busy)
{
    size_t n = (size_t)(u->y1 - u->y0) * S->W * 3;
    int64_t *dst = S->acc + (size_t)u->y0 * S->W * 3;
    pthread_mutex_lock(&S->mu);
    for (size_t i = 0; i < n; i++)
        dst[i] += sums[i];
    S->done_units++;
    S->rows_done += u->y1 - u->y0;
    S->segments += segs;
    rt_rank_stats *st = &S->stats[rank];
    st->units++;
    st->rows += u->y1 - u->y0;
    st->segments += segs;
    st->busy += busy;
    pthread_mutex_unlock(&S->mu);
}

static void *local_loop(void *arg)
{
    shared *S = arg;
    const rt_farm_job *job = S->job;
    int64_t *buf = malloc((size_t)S->band * S->W * 3 * sizeof *buf);
    if (!buf) {
        pthread_mutex_lock(&S->mu);
        S->error = RT_ENOMEM;
        pthread_mutex_unlock(&S->mu);
        return NULL;
    }
    unit u;
    while (take_unit(S, &u)) {
        size_t n = (size_t)(u.y1 - u.y0) * S->W * 3;
        memset(buf, 0, n * sizeof *buf);
        double t0 = rt_now();
        uint64_t segs = rt_render_rows(job->renderer, u.y0, u.y1, u.s0, u.s1, buf, job->threads, NULL, NULL);
        add_result(S, 0, &u, buf, segs, rt_now() - t0);
        if (S->serial && job->progress) {
            rt_progress_update(job->progress, S->rows_done, S->segments);
        }
    }
    free(buf);
    return NULL;
}

static double maxrss_mb(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0)
        return 0;
    return (double)ru.ru_maxrss / 1024.0; /* Linux reports KiB */
}

#ifdef RT_HAVE_MPI
static void nap(int *idle)
{
    /* 50 us, doubling up to 1 ms: quick replies while busy, ~0 CPU idle. */
    long ns = 50000L << (*idle < 5 ? *idle : 5);
    if (ns > 1000000L)
        ns = 1000000L;
    struct timespec ts = {0, ns};
    nanosleep(&ts, NULL);
    (*idle)++;
}

static void send_unit(const rt_farm *f, int dest, const unit *u)
{
    int32_t msg[5] = {(int32_t)u->id, (int32_t)u->y0, (int32_t)u->y1, (int32_t)u->s0, (int32_t)u->s1};
    if (MPI_Send(msg, 5, MPI_INT32_T, dest, TAG_UNIT, MPI_COMM_WORLD) != MPI_SUCCESS)
        rt_farm_fail(f, 1, "MPI_Send of a work unit to rank %d failed", dest);
}

static void send_done(const rt_farm *f, int dest)
{
    if (MPI_Send(NULL, 0, MPI_INT32_T, dest, TAG_DONE, MPI_COMM_WORLD) != MPI_SUCCESS)
        rt_farm_fail(f, 1, "MPI_Send to rank %d failed", dest);
}

static void serve(const rt_farm *f, shared *S)
{
    int nworkers = f->size - 1, finished = 0, idle = 0;
    int *outstanding = calloc((size_t)f->size, sizeof *outstanding);
    size_t cap = HDR + (size_t)S->band * S->W * 3;
    int64_t *msg = malloc(cap * sizeof *msg);
    if (!outstanding || !msg)
        rt_farm_fail(f, 1, "out of memory on rank 0");
    const rt_farm_job *job = S->job;
    for (;;) {
        pthread_mutex_lock(&S->mu);
        int all_done = S->done_units == S->nunits;
        uint64_t rows = S->rows_done, segs = S->segments;
        int err = S->error;
        pthread_mutex_unlock(&S->mu);
        if (err)
            rt_farm_fail(f, 1, "rendering on rank 0 failed: %s", rt_status_str(err));
        if (job->progress)
            rt_progress_update(job->progress, rows, segs);
        if (all_done && finished == nworkers)
            break;
        int flag = 0;
        MPI_Status status;
        if (MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status) != MPI_SUCCESS)
            rt_farm_fail(f, 1, "MPI_Iprobe failed");
        if (!flag) {
            nap(&idle);
            continue;
        }
        idle = 0;
        int src = status.MPI_SOURCE;
        if (status.MPI_TAG == TAG_HELLO) {
            int32_t want = 0;
            MPI_Recv(&want, 1, MPI_INT32_T, src, TAG_HELLO, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            unit u;
            for (int k = 0; k < want && take_unit(S, &u); k++) {
                send_unit(f, src, &u);
                outstanding[src]++;
            }
            if (outstanding[src] == 0) {
                send_done(f, src);
                finished++;
            }
        } else if (status.MPI_TAG == TAG_RESULT) {
            int count = 0;
            MPI_Get_count(&status, MPI_INT64_T, &count);
            if (count < HDR || (size_t)count > cap)
                rt_farm_fail(f, 1, "malformed result from rank %d", src);
            if (MPI_Recv(msg, count, MPI_INT64_T, src, TAG_RESULT, MPI_COMM_WORLD, MPI_STATUS_IGNORE) !=
                MPI_SUCCESS)
                rt_farm_fail(f, 1, "receiving a result from rank %d failed", src);
            if (msg[0] < 0 || (uint64_t)msg[0] >= S->nunits)
                rt_farm_fail(f, 1, "result for unknown unit %lld from rank %d", (long long)msg[0], src);
            unit u = unit_of(S, (uint32_t)msg[0]);
            if ((size_t)count != HDR + (size_t)(u.y1 - u.y0) * S->W * 3)
                rt_farm_fail(f, 1, "result of wrong size from rank %d", src);
            add_result(S, src, &u, msg + HDR, (uint64_t)msg[1], (double)msg[2] * 1e-9);
            unit next;
            if (take_unit(S, &next)) {
                send_unit(f, src, &next);
            } else if (--outstanding[src] == 0) {
                send_done(f, src);
                finished++;
            }
        } else {
            rt_farm_fail(f, 1, "unexpected message tag %d from rank %d", status.MPI_TAG, src);
        }
    }
    free(outstanding);
    free(msg);
}

typedef struct worker_poll {
    MPI_Request *req;
    int n;
} worker_poll;

static void poll_sends(void *ctx)
{
    worker_poll *w = ctx;
    int flag;
    MPI_Testall(w->n, w->req, &flag, MPI_STATUSES_IGNORE);
}

static void work(const rt_farm *f, const rt_farm_job *job, rt_rank_stats *me)
{
    const rt_renderer *r = job->renderer;
    const uint32_t W = r->p.width;
    int depth = job->prefetch > 0 ? job->prefetch : 2;
    size_t cap = HDR + (size_t)job->band * W * 3;
    int64_t *bufs[2] = {malloc(cap * sizeof(int64_t)), malloc(cap * sizeof(int64_t))};
    unit *queue = malloc((size_t)depth * sizeof *queue);
    if (!bufs[0] || !bufs[1] || !queue)
        rt_farm_fail(f, 1, "out of memory for work buffers");
    MPI_Request req[2] = {MPI_REQUEST_NULL, MPI_REQUEST_NULL};
    worker_poll wp = {req, 2};
    /* Test hook: make one rank fail, to check that the job ends promptly. */
    const char *fault = getenv("RT_FAULT_INJECT_RANK");
    if (fault && atoi(fault) == f->rank)
        rt_farm_fail(f, 1, "fault injected for testing (RT_FAULT_INJECT_RANK=%s)", fault);
    int32_t want = depth;
    if (MPI_Send(&want, 1, MPI_INT32_T, 0, TAG_HELLO, MPI_COMM_WORLD) != MPI_SUCCESS)
        rt_farm_fail(f, 1, "cannot reach rank 0");
    int qhead = 0, qlen = 0, done = 0, idle = 0, k = 0;
    for (;;) {
        /* Take in every message that is there; wait (sleeping) only when
         * there is nothing to render. */
        for (;;) {
            int flag = 0;
            MPI_Status status;
            if (MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status) != MPI_SUCCESS)
                rt_farm_fail(f, 1, "MPI_Iprobe failed");
            if (!flag) {
                if (qlen > 0 || done)
                    break;
                int sflag;
                MPI_Testall(2, req, &sflag, MPI_STATUSES_IGNORE);
                nap(&idle);
                continue;
            }
            idle = 0;
            if (status.MPI_TAG == TAG_UNIT) {
                int32_t m[5];
                MPI_Recv(m, 5, MPI_INT32_T, 0, TAG_UNIT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
                if (qlen == depth)
                    rt_farm_fail(f, 1, "received more units than requested");
                unit u = {(uint32_t)m[0], (uint32_t)m[1], (uint32_t)m[2], (uint32_t)m[3], (uint32_t)m[4]};
                if (u.y1 <= u.y0 || u.y1 > r->p.height || u.y1 - u.y0 > job->band || u.s1 <= u.s0)
                    rt_farm_fail(f, 1, "malformed work unit from rank 0");
                queue[(qhead + qlen++) % depth] = u;
            } else if (status.MPI_TAG == TAG_DONE) {
                MPI_Recv(NULL, 0, MPI_INT32_T, 0, TAG_DONE, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
                done = 1;
            } else {
                rt_farm_fail(f, 1, "unexpected message tag %d from rank 0", status.MPI_TAG);
            }
        }
        if (qlen == 0 && done)
            break;
        unit u = queue[qhead];
        qhead = (qhead + 1) % depth;
        qlen--;
        while (req[k] != MPI_REQUEST_NULL) { /* MPI_Wait would busy-poll */
            int flag = 0;
            MPI_Test(&req[k], &flag, MPI_STATUS_IGNORE);
            if (!flag)
                nap(&idle);
        }
        int64_t *b = bufs[k];
        size_t n = (size_t)(u.y1 - u.y0) * W * 3;
        memset(b, 0, (HDR + n) * sizeof *b);
        double t0 = rt_now();
        uint64_t segs = rt_render_rows(r, u.y0, u.y1, u.s0, u.s1, b + HDR, job->threads, poll_sends, &wp);
        double busy = rt_now() - t0;
        b[0] = u.id;
        b[1] = (int64_t)segs;
        b[2] = (int64_t)(busy * 1e9);
        b[3] = u.y1 - u.y0;
        me->units++;
        me->rows += u.y1 - u.y0;
        me->segments += segs;
        me->busy += busy;
        if (MPI_Isend(b, (int)(HDR + n), MPI_INT64_T, 0, TAG_RESULT, MPI_COMM_WORLD, &req[k]) != MPI_SUCCESS)
            rt_farm_fail(f, 1, "sending a result to rank 0 failed");
        k ^= 1;
    }
    /* Wait for the last results without spinning. */
    for (;;) {
        int flag = 0;
        MPI_Testall(2, req, &flag, MPI_STATUSES_IGNORE);
        if (flag)
            break;
        nap(&idle);
    }
    free(bufs[0]);
    free(bufs[1]);
    free(queue);
}
#endif /* RT_HAVE_MPI */

int rt_farm_render(const rt_farm *f, const rt_farm_job *job, rt_farm_result *res)
{
    memset(res, 0, sizeof *res);
    const rt_renderer *r = job->renderer;
    double t0 = rt_now();
    shared S;
    memset(&S, 0, sizeof S);
    pthread_mutex_init(&S.mu, NULL);
    S.job = job;
    S.W = r->p.width;
    S.H = r->p.height;
    S.band = job->band;
    S.samples = r->p.samples;
    S.nunits = (S.H + S.band - 1) / S.band;
    res->units = S.nunits;
    rt_rank_stats mine;
    memset(&mine, 0, sizeof mine);

    if (f->rank == 0) {
        S.acc = calloc((size_t)S.W * S.H * 3, sizeof *S.acc);
        S.stats = calloc((size_t)f->size, sizeof *S.stats);
        if (!S.acc || !S.stats)
            rt_farm_fail(f, 1, "out of memory for the %u x %u framebuffer", S.W, S.H);
        if (f->size == 1) {
            S.serial = 1;
            local_loop(&S);
            if (S.error)
                rt_farm_fail(f, 1, "rendering failed: %s", rt_status_str(S.error));
        }
#ifdef RT_HAVE_MPI
        else {
            pthread_t th;
            if (pthread_create(&th, NULL, local_loop, &S) != 0)
                rt_farm_fail(f, 1, "cannot start the render thread on rank 0");
            serve(f, &S);
            pthread_join(th, NULL);
        }
#endif
    }
#ifdef RT_HAVE_MPI
    else {
        work(f, job, &mine);
    }
#endif
    res->wall = rt_now() - t0;

    /* Totals: rank 0 already has every rank's counters from the results;
     * peak memory comes from each rank itself. */
    double rss = maxrss_mb();
    if (f->rank == 0) {
        S.stats[0].maxrss_mb = rss;
#ifdef RT_HAVE_MPI
        if (f->size > 1) {
            double *all = malloc((size_t)f->size * sizeof *all);
            if (!all)
                rt_farm_fail(f, 1, "out of memory");
            MPI_Gather(&rss, 1, MPI_DOUBLE, all, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
            for (int i = 0; i < f->size; i++)
                S.stats[i].maxrss_mb = all[i];
            free(all);
        }
#endif
        res->acc = S.acc;
        res->ranks = S.stats;
        res->segments = S.segments;
    } else {
#ifdef RT_HAVE_MPI
        MPI_Gather(&rss, 1, MPI_DOUBLE, NULL, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
#endif
        res->segments = mine.segments;
    }
    pthread_mutex_destroy(&S.mu);
    return RT_OK;
}
