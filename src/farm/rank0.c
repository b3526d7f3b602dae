/* rank0.c - the farm's entry point, rank 0's threads. Rank 0's main thread
 * is the server (server.c) and calls the job's hooks; a second thread
 * renders units from the same queue with the job's OpenMP threads. Alone
 * (one rank, or no MPI) the render loop calls the hooks itself. Only the
 * main thread calls MPI (MPI_THREAD_FUNNELED). Rank 0's state and its
 * verbs are root.c's: this file calls the server and root.c, the server
 * calls root.c, and root.c calls neither. */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

#ifdef RT_HAVE_MPI
#include <mpi.h>
#endif

#include "clock.h"
#include "status.h"

/* A signal arrived: save what is complete and end the job. */
static void interrupted(const rt_farm *f, rt_root *R)
{
    int sig = RT_FARM_STOPPED();
    int saved = rt_root_save_now(R);
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
        rt_farm_serve(f, job, &R, res);
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
