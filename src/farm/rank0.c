/* rank0.c - the farm's entry point, rank 0's threads. Rank 0's main thread
 * is the server (server.c) and calls the job's hooks; a second thread
 * renders units from the same queue with the job's OpenMP threads. Alone
 * (one rank, or no MPI) the render loop calls the hooks itself. Only the
 * main thread calls MPI (MPI_THREAD_FUNNELED). Rank 0's state and its
 * verbs are root.c's (its struct is private there): this file calls the
 * server and root.c, the server calls root.c, and root.c calls neither. */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

#ifdef RT_HAVE_MPI
#include <mpi.h>
#endif

#include "clock.h"
#include "status.h"

/* A signal arrived: save what is complete and end the job. */
static void interrupted(const rt_farm *f, const rt_farm_rank0 *own, rt_root *R)
{
    int sig = RT_FARM_STOPPED();
    int saved = rt_root_save_now(R);
    const rt_farm_hooks *h = &own->hooks;
    if (h->stopped) {
        uint32_t done, rows;
        rt_root_rows(R, &done, &rows);
        h->stopped(h->client, sig, saved, done, rows);
    }
    rt_farm_exit(f, RT_EXIT_INTERRUPTED);
}

/* Rank 0's own rendering (all of it when there is no server): units from
 * the shared queue, rendered as one stream so that its threads never wait
 * for each other between units. */
typedef struct local {
    rt_root *R;
    const rt_farm_job *job;
    double t0;     /* the render's time origin */
    int serial;    /* no server: the render loop calls the hooks itself */
    double *taken; /* per unit id: when it was taken */
    double last;   /* when the previous unit was done */
    /* local_poll's (the team's master alone calls it): the waits, their
     * seconds and the thread's CPU seconds in them */
    uint64_t waits;
    double waited, wait_cpu;
} local;

static int local_take(void *ctx, rt_unit *u)
{
    local *L = ctx;
    int got = rt_root_take(L->R, 0, u);
    if (got > 0)
        L->taken[u->id] = rt_now() - L->t0;
    return got;
}

/* A frame job's units may not be ready yet (the cap). When its take said
 * so, the team's master waits (rt_root_wait) until a frame is released (by
 * the main thread once the workers' sums are in; alone, by the thread whose
 * unit completes it), units are requeued, the job fails or stops, or
 * another of its threads leaves the team (local_wake). Alone, no other
 * thread hands frames on: it ticks first, so that it never waits on
 * itself. When every unit in hand is being rendered, the team waits for
 * one. It never naps and polls. */
static int local_poll(void *ctx, int idle)
{
    local *L = ctx;
    if (idle != RT_POLL_NONE_YET)
        return idle ? -1 : 0;
    if (L->serial)
        rt_root_tick(L->R);
    const double t = rt_now(), cpu = rt_sysinfo_thread_cpu();
    rt_root_wait(L->R);
    L->waits++;
    L->waited += rt_now() - t;
    L->wait_cpu += rt_sysinfo_thread_cpu() - cpu;
    return 1;
}

static void local_wake(void *ctx)
{
    local *L = ctx;
    rt_root_wake(L->R);
}

static void local_done(void *ctx, const rt_unit *u, const int64_t *sums, uint64_t segs)
{
    local *L = ctx;
    double end = rt_now() - L->t0;
    double start = rt_farm_unit_start(L->taken[u->id], &L->last, end);
    rt_root_add(L->R, u, sums, segs, start, end);
    if (L->serial)
        rt_root_tick(L->R);
}

static void *local_loop(void *arg)
{
    local *L = arg;
    uint32_t n = rt_root_units(L->R);
    L->taken = calloc(n ? n : 1, sizeof *L->taken);
    const int frames = L->job->frames != 0;
    rt_render_source src = {.take = local_take,
                            .done = local_done,
                            .poll = frames ? local_poll : NULL,
                            .wake = frames ? local_wake : NULL,
                            .ctx = L};
    int st = L->taken ? rt_farm_run_units(L->job, &src) : RT_ENOMEM;
    if (st)
        rt_root_fail(L->R, st);
    free(L->taken);
    L->taken = NULL;
    return NULL;
}

static void run_root(rt_farm *f, const rt_farm_job *job, const rt_farm_rank0 *own, rt_farm_result *res, double t0)
{
    int st;
    rt_root *R = rt_root_new(job, own, f->size, t0, &st);
    if (!R)
        rt_farm_fail(f, RT_EXIT_RUNTIME, "cannot plan the work units: %s", rt_status_str(st));
    res->units = rt_root_units(R);
    local L = {.R = R, .job = job, .t0 = t0, .serial = f->size == 1};
    if (L.serial)
        local_loop(&L);
#ifdef RT_HAVE_MPI
    else {
        pthread_t th;
        int render = !job->root_serves_only;
        if (render && pthread_create(&th, NULL, local_loop, &L) != 0)
            rt_farm_fail(f, RT_EXIT_RUNTIME, "cannot start the render thread on rank 0");
        rt_farm_serve(f, job, own, R, res);
        if (render)
            pthread_join(th, NULL);
    }
#endif
    if (RT_FARM_STOPPED())
        interrupted(f, own, R);
    rt_root_tick(R); /* the frames completed last (or restored complete) */
    int complete;
    if ((st = rt_root_error(R, &complete)) != RT_OK)
        rt_farm_fail(f, RT_EXIT_RUNTIME, "rendering failed: %s", rt_status_str(st));
    res->wall = rt_now() - t0;
    rt_root_finish(R, res);
    if (res->ranks)
        res->ranks[0].wait = L.waited;
    res->render_waits = L.waits;
    res->render_wait_cpu = L.wait_cpu;
    rt_root_free(R);
}

void rt_farm_render(rt_farm *f, const rt_farm_job *job, const rt_farm_rank0 *own, rt_farm_result *res)
{
    memset(res, 0, sizeof *res);
    rt_farm_signals_install();
    rt_farm_sync(f); /* common time origin for the trace */
    double t0 = rt_now();
    if (f->rank == 0) {
        run_root(f, job, own, res, t0);
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
