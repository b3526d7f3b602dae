/* root.c - rank 0, and the farm's entry point. Rank 0's main thread is the
 * server (server.c) and calls the job's hooks; a second thread renders
 * units from the same queue with the job's OpenMP threads. Alone (one
 * rank, or no MPI) the render loop calls the hooks itself. Only the main
 * thread calls MPI (MPI_THREAD_FUNNELED).
 *
 * Results are fixed-point sums (render.h), so the order in which they
 * arrive does not change a single bit of the image. */
#include "internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef RT_HAVE_MPI
#include <mpi.h>
#endif

#include "clock.h"
#include "mem.h"
#include "status.h"

int rt_root_take(rt_root *R, int rank, rt_unit *u)
{
    pthread_mutex_lock(&R->mu);
    int ok = !RT_FARM_STOPPED() && !R->error && rt_ledger_take(&R->led, &R->as.sched, rank, u);
    pthread_mutex_unlock(&R->mu);
    return ok;
}

/* A consistent copy of the committed counts and sums, taken under the lock
 * (other threads keep adding to the image). for_save clears the dirty
 * flag. The copy's pages are mapped up front (rt_mem_zeroed), so the copy
 * under the lock does not fault them in while the other threads wait for
 * it. Release with release(). */
static int snapshot(rt_root *R, int for_save, uint32_t **committed, int64_t **acc)
{
    size_t H = R->as.sched.height, n = rt_assembly_len(&R->as);
    *committed = malloc(H * sizeof **committed);
    *acc = rt_mem_zeroed(n * sizeof **acc);
    if (!*committed || !*acc) {
        free(*committed);
        rt_mem_free(*acc, n * sizeof **acc);
        return RT_ENOMEM;
    }
    pthread_mutex_lock(&R->mu);
    memcpy(*committed, R->as.sched.committed, H * sizeof **committed);
    memcpy(*acc, R->as.acc, n * sizeof **acc);
    if (for_save)
        R->as.dirty = 0;
    pthread_mutex_unlock(&R->mu);
    return RT_OK;
}

static void release(rt_root *R, uint32_t *committed, int64_t *acc)
{
    free(committed);
    rt_mem_free(acc, rt_assembly_len(&R->as) * sizeof *acc);
}

/* After each progressive pass but the last (the final image, which the
 * caller writes): a consistent image for hooks.pass. When the last passes
 * complete together (units of later passes came in before an early one),
 * the last but one is still shown: a progressive run always shows one. */
static void pass_hook(rt_root *R, uint32_t pass)
{
    const rt_farm_hooks *h = &R->job->hooks;
    if (pass >= R->as.sched.passes)
        pass = R->as.sched.passes - 1;
    if (!h->pass || pass == 0 || pass <= R->previewed)
        return;
    R->previewed = pass;
    uint32_t *committed;
    int64_t *acc;
    if (snapshot(R, 0, &committed, &acc) != RT_OK)
        return;
    h->pass(h->ctx, pass, rt_sched_pass_end(&R->as.sched, pass - 1), committed, acc);
    release(R, committed, acc);
}

/* hooks.save when due and something new was committed (or now, with
 * force), from a snapshot so that rendering goes on meanwhile. Returns
 * whether the state is saved. */
static int save_hook(rt_root *R, int force)
{
    const rt_farm_hooks *h = &R->job->hooks;
    if (!h->save)
        return 0;
    double now = rt_now();
    if (!force && now - R->last_save < h->save_interval)
        return 0;
    R->last_save = now;
    pthread_mutex_lock(&R->mu);
    int dirty = R->as.dirty;
    pthread_mutex_unlock(&R->mu);
    if (!dirty && !force)
        return 1;
    uint32_t *committed;
    int64_t *acc;
    int st = snapshot(R, 1, &committed, &acc);
    if (!st) {
        st = h->save(h->ctx, committed, acc);
        release(R, committed, acc);
    }
    if (st) {
        pthread_mutex_lock(&R->mu);
        R->as.dirty = 1;
        pthread_mutex_unlock(&R->mu);
    }
    return !st;
}

void rt_root_tick(rt_root *R)
{
    const rt_farm_hooks *h = &R->job->hooks;
    pthread_mutex_lock(&R->mu);
    uint64_t rows = R->as.sched.rows_done, segs = R->as.segments;
    uint32_t done = R->as.passes_done, passes = R->as.sched.passes;
    int ready = R->as.pass_ready;
    R->as.pass_ready = 0;
    pthread_mutex_unlock(&R->mu);
    if (h->progress)
        h->progress(h->ctx, done < passes ? done + 1 : done, rows, segs);
    if (ready)
        pass_hook(R, done);
    save_hook(R, 0);
}

int rt_root_save_now(rt_root *R) { return save_hook(R, 1); }

/* A signal arrived: save what is complete and end the job. */
static void interrupted(const rt_farm *f, rt_root *R)
{
    int sig = RT_FARM_STOPPED();
    int saved = save_hook(R, 1);
    const rt_farm_hooks *h = &R->job->hooks;
    if (h->stopped)
        h->stopped(h->ctx, sig, saved, R->as.sched.rows_done, R->as.sched.height);
    rt_farm_exit(f, RT_EXIT_INTERRUPTED);
}

/* Rank 0's own rendering (all of it when there is no server): units from
 * the shared queue, rendered as one stream so that its threads never wait
 * for each other between units. */
typedef struct local {
    rt_root *R;
    double *taken; /* per unit id: when it was taken */
    double last;   /* when the previous unit was done */
} local;

static int local_take(void *ctx, rt_unit *u)
{
    local *L = ctx;
    if (!rt_root_take(L->R, 0, u))
        return 0;
    L->taken[u->id] = rt_now() - L->R->t0;
    return 1;
}

static void local_done(void *ctx, const rt_unit *u, const int64_t *sums, uint64_t segs)
{
    local *L = ctx;
    rt_root *R = L->R;
    double end = rt_now() - R->t0;
    double start = rt_farm_unit_start(L->taken[u->id], &L->last, end);
    pthread_mutex_lock(&R->mu);
    int st = rt_ledger_done(&R->led, 0, u->id) && rt_ledger_in(&R->led, 0, u->id)
                 ? rt_assembly_add(&R->as, 0, u, sums, segs, start, end)
                 : RT_EINVAL;
    if (st && !R->error)
        R->error = st;
    pthread_mutex_unlock(&R->mu);
    if (L->R->serial)
        rt_root_tick(L->R);
}

static void *local_loop(void *arg)
{
    rt_root *R = arg;
    local L = {R, calloc(R->as.sched.n_units ? R->as.sched.n_units : 1, sizeof *L.taken), 0};
    rt_render_source src = {local_take, local_done, NULL, &L};
    int st = L.taken ? rt_farm_run_units(R->job, &src) : RT_ENOMEM;
    if (st) {
        pthread_mutex_lock(&R->mu);
        R->error = st;
        pthread_mutex_unlock(&R->mu);
    }
    free(L.taken);
    return NULL;
}

static void run_root(rt_farm *f, const rt_farm_job *job, rt_farm_result *res, double t0)
{
    rt_root R;
    memset(&R, 0, sizeof R);
    pthread_mutex_init(&R.mu, NULL);
    R.job = job;
    R.t0 = R.last_save = t0;
    int st = rt_assembly_init(&R.as, &job->renderer->job, &job->sched, job->committed, job->acc, f->size,
                              job->trace);
    if (!st)
        st = rt_ledger_init(&R.led, &R.as.sched, f->size);
    if (st)
        rt_farm_fail(f, RT_EXIT_RUNTIME, "cannot plan the work units: %s", rt_status_str(st));
    res->units = R.as.sched.n_units;
    if (f->size == 1) {
        R.serial = 1;
        local_loop(&R);
    }
#ifdef RT_HAVE_MPI
    else {
        pthread_t th;
        int render = !job->root_serves_only;
        if (render && pthread_create(&th, NULL, local_loop, &R) != 0)
            rt_farm_fail(f, RT_EXIT_RUNTIME, "cannot start the render thread on rank 0");
        rt_farm_serve(f, &R, res);
        if (render)
            pthread_join(th, NULL);
    }
#endif
    if (RT_FARM_STOPPED())
        interrupted(f, &R);
    if (R.error)
        rt_farm_fail(f, RT_EXIT_RUNTIME, "rendering failed: %s", rt_status_str(R.error));
    res->wall = rt_now() - t0;
    R.as.stats[0].maxrss_mb = rt_sysinfo_peak_mb();
    rt_sysinfo_hostname(R.as.stats[0].host, sizeof R.as.stats[0].host);
    res->ranks = R.as.stats;
    res->segments = R.as.segments;
    res->trace = R.as.trace;
    res->n_trace = R.as.n_trace;
    R.as.stats = NULL; /* the caller's now */
    R.as.trace = NULL;
    rt_assembly_free(&R.as);
    rt_ledger_free(&R.led);
    pthread_mutex_destroy(&R.mu);
}

void rt_farm_render(rt_farm *f, const rt_farm_job *job, rt_farm_result *res)
{
    memset(res, 0, sizeof *res);
    rt_farm_signals_install();
#ifdef RT_HAVE_MPI
    if (f->mpi && f->size > 1)
        MPI_Barrier(MPI_COMM_WORLD); /* common time origin for the trace */
#endif
    double t0 = rt_now();
    if (f->rank == 0) {
        run_root(f, job, res, t0);
        return;
    }
#ifdef RT_HAVE_MPI
    rt_rank_stats mine;
    memset(&mine, 0, sizeof mine);
    rt_farm_work(f, job, &mine, t0);
    res->wall = rt_now() - t0;
    res->segments = (uint64_t)mine.segments;
#endif
}
