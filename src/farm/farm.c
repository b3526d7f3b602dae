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
 * hand and a slow rank simply gets fewer bands.
 *
 * Every rank renders its units as one stream (rt_render_stream): no barrier
 * between units. On a worker, the stream's master thread (the main thread)
 * also does the MPI between its pixels: results go out as soon as they are
 * done, units are received as they come.
 *
 * Results are fixed-point sums (see render.h), so the order in which they
 * arrive does not change a single bit of the image. */
#define _GNU_SOURCE
#include "farm.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#ifdef RT_HAVE_MPI
#include <mpi.h>
#endif

#include "array.h"
#include "clock.h"
#include "mem.h"
#include "status.h"

enum { TAG_HELLO = 11, TAG_UNIT = 12, TAG_DONE = 13, TAG_RESULT = 14 };
/* result header: unit id, segments, start ns, end ns (worker clock, since
 * the common start) */
#define HDR 4

/* Set by the signal handler; every render loop watches it. */
static volatile sig_atomic_t g_stop;

static void on_signal(int sig) { g_stop = sig; }

typedef struct pending {
    rt_unit unit;
    int64_t *sums;
} pending;

typedef struct shared {
    pthread_mutex_t mu;
    const rt_farm_job *job;
    rt_sched sched;
    uint32_t W;
    uint64_t segments;
    int64_t *acc;
    rt_rank_stats *stats;
    rt_trace_event *trace;
    size_t n_trace, cap_trace;
    double t0;
    int serial; /* no server: the render loop reports progress itself */
    int error;
    int dirty;      /* samples committed since the last checkpoint */
    struct pending *pending; /* results that arrived before their predecessors */
    size_t n_pending, cap_pending;
    uint32_t passes_done;  /* progressive passes complete */
    int pass_ready;        /* a pass completed: the server writes the preview */
    double last_ckpt;
    int ckpt_warned;
} shared;

/* ---- set-up ------------------------------------------------------------ */

/* The CPUs this rank may run threads on, and how many threads fit there.
 * With OpenMP thread binding on (OMP_PROC_BIND), the runtime has already
 * pinned this thread to the first of its places when main starts, so the
 * affinity mask shows one core: the places say where the team will run,
 * one thread per place. */
static int affinity(cpu_set_t *set, int *bound)
{
    CPU_ZERO(set);
    *bound = 0;
#ifdef _OPENMP
    int places = omp_get_num_places();
    if (omp_get_proc_bind() != omp_proc_bind_false && places > 0) {
        for (int p = 0; p < places; p++) {
            int n = omp_get_place_num_procs(p);
            int *ids = n > 0 ? malloc((size_t)n * sizeof *ids) : NULL;
            if (ids) {
                omp_get_place_proc_ids(p, ids);
                for (int i = 0; i < n; i++)
                    if (ids[i] >= 0 && ids[i] < CPU_SETSIZE)
                        CPU_SET(ids[i], set);
            }
            free(ids);
        }
        if (CPU_COUNT(set) > 0) {
            *bound = 1;
            return places;
        }
        CPU_ZERO(set);
    }
#endif
    if (sched_getaffinity(0, sizeof *set, set) == 0 && CPU_COUNT(set) > 0)
        return CPU_COUNT(set);
    long online = sysconf(_SC_NPROCESSORS_ONLN);
    return online > 0 ? (int)online : 1;
}

#ifdef RT_HAVE_MPI
/* Whether an MPI launcher started this process: mpirun (Open MPI, MPICH,
 * Intel MPI, MVAPICH) and srun with a PMI or PMIx plugin all leave one of
 * these in the environment. A process started by hand is a job of one rank
 * and needs no MPI: Open MPI would start it as a singleton, which forks an
 * orted and costs ~0.4 s of every command here. RT_MPI_INIT=1 forces
 * MPI_Init for a launcher this list does not know, 0 skips it. */
static int launched_by_mpi(void)
{
    static const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "PMI_FD",
                                       "PMI_PORT", "MPI_LOCALNRANKS", "MV2_COMM_WORLD_RANK"};
    const char *force = getenv("RT_MPI_INIT");
    if (force && *force)
        return strcmp(force, "0") != 0;
    for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++)
        if (getenv(vars[i]))
            return 1;
    return 0;
}
#endif

int rt_farm_init(rt_farm *f, int *argc, char ***argv)
{
    memset(f, 0, sizeof *f);
    f->size = f->mask_share = 1;
    cpu_set_t mask;
    f->cores = affinity(&mask, &f->omp_bound);
#ifdef RT_HAVE_MPI
    if (!launched_by_mpi())
        return RT_OK;
    int provided = 0;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
        return RT_EIO;
    f->mpi = 1;
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &f->rank);
    MPI_Comm_size(MPI_COMM_WORLD, &f->size);
    /* Which ranks of this node run on exactly the same CPUs? */
    MPI_Comm node;
    if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, f->rank, MPI_INFO_NULL, &node) == MPI_SUCCESS) {
        int lrank = 0, lsize = 1;
        MPI_Comm_rank(node, &lrank);
        MPI_Comm_size(node, &lsize);
        cpu_set_t *all = malloc((size_t)lsize * sizeof *all);
        if (all && MPI_Allgather(&mask, (int)sizeof mask, MPI_BYTE, all, (int)sizeof mask, MPI_BYTE, node) ==
                       MPI_SUCCESS) {
            f->mask_share = 0;
            for (int r = 0; r < lsize; r++) {
                if (CPU_EQUAL(&all[r], &mask)) {
                    if (r < lrank)
                        f->mask_index++;
                    f->mask_share++;
                }
            }
        }
        free(all);
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

void rt_farm_exit(const rt_farm *f, int code)
{
    fflush(stdout);
    fflush(stderr);
#ifdef RT_HAVE_MPI
    /* Other ranks may be mid-render: a non-zero exit makes mpirun end them
     * (MPI_Abort would add its banner to an expected, documented stop). */
    if (f->mpi && f->size > 1)
        _exit(code);
    if (f->mpi)
        MPI_Finalize();
#else
    (void)f;
#endif
    exit(code);
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
    int share = f->mask_share > 0 ? f->mask_share : 1;
    int n = f->cores / share + (f->mask_index < f->cores % share ? 1 : 0);
    return n > 0 ? n : 1;
}

int rt_farm_bind_threads(const rt_farm *f, int threads)
{
    const char *env = getenv("RT_BIND");
    if (f->omp_bound || getenv("OMP_PROC_BIND") || (env && !strcmp(env, "0")))
        return 0;
    /* affinity() read this mask at rt_farm_init; nothing has changed it */
    cpu_set_t mask;
    if (sched_getaffinity(0, sizeof mask, &mask) != 0 || (long)threads * f->mask_share != CPU_COUNT(&mask))
        return 0;
    /* this rank's CPUs: the mask's CPUs [first, first + threads) */
    const int first = f->mask_index * threads;
    int cpu[CPU_SETSIZE], n = 0;
    for (int c = 0; c < CPU_SETSIZE; c++)
        if (CPU_ISSET(c, &mask)) {
            if (n >= first && n < first + threads)
                cpu[n - first] = c;
            n++;
        }
    int bound = 0;
#ifdef _OPENMP
#pragma omp parallel num_threads(threads) reduction(+ : bound)
    {
        const int k = omp_get_thread_num();
        cpu_set_t one;
        CPU_ZERO(&one);
        CPU_SET(cpu[k], &one);
        bound += omp_get_num_threads() == threads && pthread_setaffinity_np(pthread_self(), sizeof one, &one) == 0;
    }
#else
    (void)cpu;
#endif
    return bound == threads;
}

/* ---- rank 0: queue, results, checkpoints --------------------------------- */

static int take_unit(shared *S, rt_unit *u)
{
    pthread_mutex_lock(&S->mu);
    int ok = !g_stop && !S->error && rt_sched_next(&S->sched, u);
    pthread_mutex_unlock(&S->mu);
    return ok;
}

static void commit(shared *S, const rt_unit *u, const int64_t *sums)
{
    size_t n = (size_t)(u->y1 - u->y0) * S->W * 3;
    int64_t *dst = S->acc + (size_t)u->y0 * S->W * 3;
    for (size_t i = 0; i < n; i++)
        dst[i] += sums[i];
    rt_sched_commit(&S->sched, u);
    S->dirty = 1;
    /* A progressive pass is complete when every row has its samples (an
     * O(height) scan, so only in progressive runs). */
    const rt_sched *sc = &S->sched;
    while (sc->passes > 1 && S->passes_done < sc->passes &&
           rt_sched_min_committed(sc) >= rt_sched_pass_end(sc, S->passes_done)) {
        S->passes_done++;
        S->pass_ready = 1;
    }
}

/* Adds a finished unit to the image in commit order (see schedule.h):
 * early arrivals wait in S->pending, which never holds more than the units
 * in flight. */
static void add_result(shared *S, int rank, const rt_unit *u, const int64_t *sums, uint64_t segs, double start,
                       double end)
{
    pthread_mutex_lock(&S->mu);
    if (rt_sched_can_commit(&S->sched, u)) {
        commit(S, u, sums);
        for (size_t i = 0; i < S->n_pending;) {
            if (rt_sched_can_commit(&S->sched, &S->pending[i].unit)) {
                commit(S, &S->pending[i].unit, S->pending[i].sums);
                free(S->pending[i].sums);
                S->pending[i] = S->pending[--S->n_pending];
                i = 0; /* a commit may unblock an earlier entry */
            } else {
                i++;
            }
        }
    } else {
        size_t n = (size_t)(u->y1 - u->y0) * S->W * 3;
        int64_t *copy = malloc(n * sizeof *copy);
        if (!copy || rt_array_reserve((void **)&S->pending, &S->cap_pending, S->n_pending + 1, sizeof *S->pending)) {
            free(copy);
            S->error = RT_ENOMEM;
        } else {
            memcpy(copy, sums, n * sizeof *copy);
            S->pending[S->n_pending].unit = *u;
            S->pending[S->n_pending++].sums = copy;
        }
    }
    S->segments += segs;
    rt_rank_stats *st = &S->stats[rank];
    st->units++;
    st->rows += (double)(u->y1 - u->y0) * (u->s1 - u->s0) / S->sched.samples;
    st->segments += (double)segs;
    st->busy += end - start;
    if (S->job->trace) { /* out of memory: the trace misses events, the render goes on */
        if (rt_array_reserve((void **)&S->trace, &S->cap_trace, S->n_trace + 1, sizeof *S->trace) == RT_OK)
            S->trace[S->n_trace++] = (rt_trace_event){rank, *u, start, end};
    }
    pthread_mutex_unlock(&S->mu);
}

/* Sums in the framebuffer, and so in a snapshot of it. */
static size_t snapshot_len(const shared *S)
{
    return (size_t)S->sched.height * S->W * 3;
}

/* A consistent copy of the committed counts and sums, taken under the lock
 * (other threads keep adding to S->acc). for_checkpoint marks the state as
 * saved. The copy's pages are mapped up front (rt_mem_zeroed), so the copy
 * under the lock does not fault them in while the other threads wait for
 * it. Release *acc with rt_mem_free. */
static int snapshot(shared *S, int for_checkpoint, uint32_t **committed, int64_t **acc)
{
    size_t H = S->sched.height, n = snapshot_len(S);
    *committed = malloc(H * sizeof **committed);
    *acc = rt_mem_zeroed(n * sizeof **acc);
    if (!*committed || !*acc) {
        free(*committed);
        rt_mem_free(*acc, n * sizeof **acc);
        return RT_ENOMEM;
    }
    pthread_mutex_lock(&S->mu);
    memcpy(*committed, S->sched.committed, H * sizeof **committed);
    memcpy(*acc, S->acc, n * sizeof **acc);
    if (for_checkpoint)
        S->dirty = 0;
    pthread_mutex_unlock(&S->mu);
    return RT_OK;
}

/* After each progressive pass: hand the caller a consistent image. */
static void maybe_preview(shared *S)
{
    const rt_farm_job *job = S->job;
    pthread_mutex_lock(&S->mu);
    int ready = S->pass_ready;
    uint32_t pass = S->passes_done;
    S->pass_ready = 0;
    pthread_mutex_unlock(&S->mu);
    if (!ready)
        return;
    if (job->progress)
        job->progress->pass = (int)(pass < S->sched.passes ? pass + 1 : pass);
    if (!job->on_pass || pass >= S->sched.passes)
        return; /* the last pass is the final image, written by the caller */
    uint32_t *committed;
    int64_t *acc;
    if (snapshot(S, 0, &committed, &acc) != RT_OK)
        return;
    job->on_pass(job->on_pass_ctx, pass, rt_sched_pass_end(&S->sched, pass - 1), committed, acc);
    free(committed);
    rt_mem_free(acc, snapshot_len(S) * sizeof *acc);
}

/* Writes the checkpoint when due and something new was committed (or now,
 * with force), from a snapshot so that rendering goes on meanwhile. */
static void maybe_checkpoint(shared *S, int force)
{
    const rt_farm_job *job = S->job;
    if (!job->checkpoint)
        return;
    double now = rt_now();
    if (!force && now - S->last_ckpt < job->checkpoint_interval)
        return;
    S->last_ckpt = now;
    pthread_mutex_lock(&S->mu);
    int dirty = S->dirty;
    pthread_mutex_unlock(&S->mu);
    if (!dirty && !force)
        return;
    uint32_t *committed;
    int64_t *acc;
    int st = snapshot(S, 1, &committed, &acc);
    if (!st) {
        st = rt_ckpt_write(job->checkpoint, &job->ckpt_job, committed, acc);
        free(committed);
        rt_mem_free(acc, snapshot_len(S) * sizeof *acc);
    }
    if (st) {
        pthread_mutex_lock(&S->mu);
        S->dirty = 1;
        pthread_mutex_unlock(&S->mu);
        if (!S->ckpt_warned)
            fprintf(stderr, "rt-mpi: warning: cannot write checkpoint %s: %s (rendering goes on; will retry)\n",
                    job->checkpoint, rt_status_str(st));
        S->ckpt_warned = 1;
    }
}

/* A signal arrived: save what is complete and end the job. */
static void interrupted(const rt_farm *f, shared *S)
{
    int sig = g_stop;
    const rt_farm_job *job = S->job;
    if (job->progress && job->progress->enabled && job->progress->tty)
        fputc('\n', stderr);
    if (job->checkpoint) {
        maybe_checkpoint(S, 1);
        fprintf(stderr, "rt-mpi: interrupted by signal %d: checkpoint %s holds %u of %u rows; rerun with --resume\n",
                sig, job->checkpoint, S->sched.rows_done, S->sched.height);
    } else {
        fprintf(stderr, "rt-mpi: interrupted by signal %d (no checkpoint file)\n", sig);
    }
    fflush(stderr);
    rt_farm_exit(f, RT_EXIT_INTERRUPTED);
}

/* A unit's place in the rank's busy time and trace: units overlap in a
 * stream, so each counts from when it was taken or the previous unit was
 * done, whichever is later, and every moment counts once. *last is when the
 * previous unit was done; it becomes end. */
static double unit_start(double taken, double *last, double end)
{
    double start = taken > *last ? taken : *last;
    *last = end;
    return start;
}

/* --empty-units (a benchmark of the farm itself): the zero sums of an
 * n-entry unit, from a buffer that grows to the largest unit; NULL when out
 * of memory. */
static const int64_t *zero_sums(int64_t **buf, size_t *cap, size_t n)
{
    if (n > *cap) {
        free(*buf);
        *cap = 0;
        if (!(*buf = calloc(n, sizeof **buf)))
            return NULL;
        *cap = n;
    }
    return *buf;
}

/* Rank 0's own rendering (all of it when there is no server): units from
 * the shared queue, rendered as one stream (rt_render_stream) so that its
 * threads never wait for each other between units. */
typedef struct local {
    shared *S;
    double *taken; /* per unit id: when it was taken */
    double last;   /* when the previous unit was done */
} local;

static int local_take(void *ctx, rt_unit *u)
{
    local *L = ctx;
    if (!take_unit(L->S, u))
        return 0;
    L->taken[u->id] = rt_now() - L->S->t0;
    return 1;
}

static void local_done(void *ctx, const rt_unit *u, const int64_t *sums, uint64_t segs)
{
    local *L = ctx;
    shared *S = L->S;
    double end = rt_now() - S->t0;
    add_result(S, 0, u, sums, segs, unit_start(L->taken[u->id], &L->last, end), end);
    if (S->serial) {
        const rt_farm_job *job = S->job;
        if (job->progress)
            rt_progress_update(job->progress, S->sched.rows_done, S->segments);
        maybe_preview(S);
        maybe_checkpoint(S, 0);
    }
}

/* --empty-units: every unit adds nothing, without rendering. */
static void empty_loop(shared *S)
{
    int64_t *zero = NULL;
    size_t cap = 0;
    rt_unit u;
    while (take_unit(S, &u)) {
        const int64_t *sums = zero_sums(&zero, &cap, (size_t)(u.y1 - u.y0) * S->W * 3);
        if (!sums) {
            pthread_mutex_lock(&S->mu);
            S->error = RT_ENOMEM;
            pthread_mutex_unlock(&S->mu);
            break;
        }
        double t = rt_now() - S->t0;
        add_result(S, 0, &u, sums, 0, t, t);
    }
    free(zero);
}

static void *local_loop(void *arg)
{
    shared *S = arg;
    const rt_farm_job *job = S->job;
    if (job->empty_units) {
        empty_loop(S);
        return NULL;
    }
    local L = {S, calloc(S->sched.n_units ? S->sched.n_units : 1, sizeof *L.taken), 0};
    rt_render_source src = {local_take, local_done, NULL, &L};
    int st = L.taken ? rt_render_stream(job->renderer, job->threads, &src) : RT_ENOMEM;
    if (st) {
        pthread_mutex_lock(&S->mu);
        S->error = st;
        pthread_mutex_unlock(&S->mu);
    }
    free(L.taken);
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

/* Open MPI's ob1 often pulls a message in on one MPI_Iprobe and reports it
 * on the next: probe twice before going to sleep, or every message costs a
 * back-off period (measured: 3.3 ms -> 0.4 ms per round trip). */
static int probe(int source, int *flag, MPI_Status *status)
{
    int rc = MPI_Iprobe(source, MPI_ANY_TAG, MPI_COMM_WORLD, flag, status);
    if (rc == MPI_SUCCESS && !*flag)
        rc = MPI_Iprobe(source, MPI_ANY_TAG, MPI_COMM_WORLD, flag, status);
    return rc;
}

static void send_unit(const rt_farm *f, int dest, const rt_unit *u)
{
    uint32_t msg[5] = {u->id, u->y0, u->y1, u->s0, u->s1};
    if (MPI_Send(msg, 5, MPI_UINT32_T, dest, TAG_UNIT, MPI_COMM_WORLD) != MPI_SUCCESS)
        rt_farm_fail(f, 1, "MPI_Send of a work unit to rank %d failed", dest);
}

static void send_done(const rt_farm *f, int dest)
{
    if (MPI_Send(NULL, 0, MPI_UINT32_T, dest, TAG_DONE, MPI_COMM_WORLD) != MPI_SUCCESS)
        rt_farm_fail(f, 1, "MPI_Send to rank %d failed", dest);
}

static void serve(const rt_farm *f, shared *S)
{
    int nworkers = f->size - 1, finished = 0, idle = 0;
    int *outstanding = calloc((size_t)f->size, sizeof *outstanding);
    int64_t *msg = NULL;
    size_t cap = 0;
    if (!outstanding)
        rt_farm_fail(f, 1, "out of memory on rank 0");
    const rt_farm_job *job = S->job;
    for (;;) {
        if (g_stop)
            return; /* the caller saves and ends the job */
        pthread_mutex_lock(&S->mu);
        int all_done = S->sched.units_done == S->sched.n_units;
        uint64_t rows = S->sched.rows_done, segs = S->segments;
        int err = S->error;
        pthread_mutex_unlock(&S->mu);
        if (err)
            rt_farm_fail(f, 1, "rendering on rank 0 failed: %s", rt_status_str(err));
        if (job->progress)
            rt_progress_update(job->progress, rows, segs);
        maybe_preview(S);
        maybe_checkpoint(S, 0);
        if (all_done && finished == nworkers)
            break;
        int flag = 0;
        MPI_Status status;
        if (probe(MPI_ANY_SOURCE, &flag, &status) != MPI_SUCCESS)
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
            rt_unit u;
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
            if (count < HDR)
                rt_farm_fail(f, 1, "malformed result from rank %d", src);
            if ((size_t)count > cap) {
                int64_t *q = realloc(msg, (size_t)count * sizeof *q);
                if (!q)
                    rt_farm_fail(f, 1, "out of memory on rank 0");
                msg = q;
                cap = (size_t)count;
            }
            if (MPI_Recv(msg, count, MPI_INT64_T, src, TAG_RESULT, MPI_COMM_WORLD, MPI_STATUS_IGNORE) !=
                MPI_SUCCESS)
                rt_farm_fail(f, 1, "receiving a result from rank %d failed", src);
            const rt_unit *u = msg[0] >= 0 && msg[0] <= UINT32_MAX ? rt_sched_unit(&S->sched, (uint32_t)msg[0]) : NULL;
            if (!u)
                rt_farm_fail(f, 1, "result for unknown unit %lld from rank %d", (long long)msg[0], src);
            rt_unit done = *u;
            if ((size_t)count != HDR + (size_t)(done.y1 - done.y0) * S->W * 3)
                rt_farm_fail(f, 1, "result of wrong size from rank %d", src);
            add_result(S, src, &done, msg + HDR, (uint64_t)msg[1], (double)msg[2] * 1e-9, (double)msg[3] * 1e-9);
            rt_unit next;
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

/* A worker: its units come from rank 0 and its results go back by MPI,
 * which only its main thread may call (MPI_THREAD_FUNNELED), while any
 * thread of the render stream takes units and hands in results. So the
 * stream's take and done only move units and results through this state,
 * under mu; poll, on the main thread, does the MPI: it posts the results
 * ready, completes sends, and receives units. */
enum { RES_FREE, RES_FILLING, RES_READY, RES_SENDING };

typedef struct result {
    int64_t *buf; /* HDR + sums */
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
    const size_t n = HDR + (size_t)(u->y1 - u->y0) * w->job->renderer->job.width * 3;
    double end = rt_now() - w->t_start, taken = 0;
    pthread_mutex_lock(&w->mu);
    for (int k = 0; k < w->depth; k++)
        if (w->hand[k].used && w->hand[k].id == u->id) {
            taken = w->hand[k].taken;
            w->hand[k].used = 0;
            break;
        }
    const double start = unit_start(taken, &w->last_end, end);
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
        memcpy(r->buf + HDR, sums, (n - HDR) * sizeof *sums);
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
    rt_rank_stats *me = w->me;
    me->units++;
    me->rows += (double)(u->y1 - u->y0) * (u->s1 - u->s0) / w->job->renderer->job.samples;
    me->segments += (double)segs;
    me->busy += end - start;
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
            if (MPI_Isend(r->buf, (int)r->len, MPI_INT64_T, 0, TAG_RESULT, MPI_COMM_WORLD, &r->req) != MPI_SUCCESS)
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
        if (g_stop)
            return 1; /* the stream sees the stop too; wake its threads */
        int flag = 0;
        MPI_Status status;
        if (probe(0, &flag, &status) != MPI_SUCCESS)
            rt_farm_fail(w->f, 1, "MPI_Iprobe failed");
        if (!flag)
            break;
        got = 1;
        if (status.MPI_TAG == TAG_UNIT) {
            uint32_t m[5];
            MPI_Recv(m, 5, MPI_UINT32_T, 0, TAG_UNIT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
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
        } else if (status.MPI_TAG == TAG_DONE) {
            MPI_Recv(NULL, 0, MPI_UINT32_T, 0, TAG_DONE, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
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
        nap(&w->idle);
        w->me->wait += rt_now() - t0;
    } else {
        w->me->comm += rt_now() - t0;
    }
    return got;
}

static void work(const rt_farm *f, const rt_farm_job *job, rt_rank_stats *me, double t_start)
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
    /* Test hook: make one rank fail, to check that the job ends promptly. */
    const char *fault = getenv("RT_FAULT_INJECT_RANK");
    if (fault && atoi(fault) == f->rank)
        rt_farm_fail(f, 1, "fault injected for testing (RT_FAULT_INJECT_RANK=%s)", fault);
    int32_t want = w.depth;
    if (MPI_Send(&want, 1, MPI_INT32_T, 0, TAG_HELLO, MPI_COMM_WORLD) != MPI_SUCCESS)
        rt_farm_fail(f, 1, "cannot reach rank 0");
    if (job->empty_units) {
        /* --empty-units: every unit adds nothing, without rendering */
        int64_t *zero = NULL;
        size_t cap = 0;
        rt_unit u;
        int got;
        while (!g_stop && (got = worker_take(&w, &u)) != 0) {
            if (got > 0) {
                const int64_t *sums = zero_sums(&zero, &cap, (size_t)(u.y1 - u.y0) * job->renderer->job.width * 3);
                if (!sums)
                    rt_farm_fail(f, 1, "out of memory for work buffers");
                worker_done(&w, &u, sums, 0);
            }
            worker_poll(&w, got < 0);
        }
        free(zero);
    } else {
        rt_render_source src = {worker_take, worker_done, worker_poll, &w};
        int st = rt_render_stream(job->renderer, job->threads, &src);
        if (st)
            rt_farm_fail(f, 1, "rendering failed: %s", rt_status_str(st));
    }
    if (g_stop)
        worker_stop();
    /* The last results out, without spinning. */
    while (!worker_send(&w))
        nap(&w.idle);
    for (size_t k = 0; k < w.n_res; k++)
        free(w.res[k].buf);
    free(w.res);
    free(w.queue);
    free(w.hand);
    pthread_mutex_destroy(&w.mu);
}
#endif /* RT_HAVE_MPI */

static void install_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGUSR1, &sa, NULL);
}

const volatile sig_atomic_t *rt_farm_stop_flag(void) { return &g_stop; }

int rt_farm_render(const rt_farm *f, const rt_farm_job *job, rt_farm_result *res)
{
    memset(res, 0, sizeof *res);
    const rt_renderer *r = job->renderer;
    install_signals();
#ifdef RT_HAVE_MPI
    if (f->mpi && f->size > 1)
        MPI_Barrier(MPI_COMM_WORLD); /* common time origin for the trace */
#endif
    double t0 = rt_now();
    rt_rank_stats mine;
    memset(&mine, 0, sizeof mine);

    if (f->rank == 0) {
        shared S;
        memset(&S, 0, sizeof S);
        pthread_mutex_init(&S.mu, NULL);
        S.job = job;
        S.W = r->job.width;
        S.acc = job->acc;
        S.t0 = t0;
        S.last_ckpt = t0;
        int st = rt_sched_init(&S.sched, &r->job, &job->sched, job->committed);
        S.stats = calloc((size_t)f->size, sizeof *S.stats);
        if (st || !S.stats)
            rt_farm_fail(f, 1, "cannot plan the work units: %s", rt_status_str(st ? st : RT_ENOMEM));
        res->units = S.sched.n_units;
        if (f->size == 1) {
            S.serial = 1;
            local_loop(&S);
        }
#ifdef RT_HAVE_MPI
        else {
            pthread_t th;
            int local = !job->root_serves_only;
            if (local && pthread_create(&th, NULL, local_loop, &S) != 0)
                rt_farm_fail(f, 1, "cannot start the render thread on rank 0");
            serve(f, &S);
            if (local)
                pthread_join(th, NULL);
        }
#endif
        if (g_stop)
            interrupted(f, &S);
        if (S.error)
            rt_farm_fail(f, 1, "rendering failed: %s", rt_status_str(S.error));
        res->wall = rt_now() - t0;
        S.stats[0].maxrss_mb = maxrss_mb();
#ifdef RT_HAVE_MPI
        if (f->mpi && f->size > 1) {
            /* Workers report their own wait/comm time and peak memory. */
            double *all = malloc((size_t)f->size * 3 * sizeof *all);
            double me3[3] = {0, 0, S.stats[0].maxrss_mb};
            if (!all)
                rt_farm_fail(f, 1, "out of memory");
            MPI_Gather(me3, 3, MPI_DOUBLE, all, 3, MPI_DOUBLE, 0, MPI_COMM_WORLD);
            for (int i = 1; i < f->size; i++) {
                S.stats[i].wait = all[3 * i];
                S.stats[i].comm = all[3 * i + 1];
                S.stats[i].maxrss_mb = all[3 * i + 2];
            }
            free(all);
        }
#endif
        res->ranks = S.stats;
        res->segments = S.segments;
        res->trace = S.trace;
        res->n_trace = S.n_trace;
        for (size_t i = 0; i < S.n_pending; i++)
            free(S.pending[i].sums);
        free(S.pending);
        rt_sched_free(&S.sched);
        pthread_mutex_destroy(&S.mu);
    } else {
#ifdef RT_HAVE_MPI
        work(f, job, &mine, t0);
        res->wall = rt_now() - t0;
        double me3[3] = {mine.wait, mine.comm, maxrss_mb()};
        MPI_Gather(me3, 3, MPI_DOUBLE, NULL, 3, MPI_DOUBLE, 0, MPI_COMM_WORLD);
        res->segments = (uint64_t)mine.segments;
#endif
    }
    return RT_OK;
}
