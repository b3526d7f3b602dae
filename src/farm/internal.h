/* internal.h - what the farm's files share; no other layer includes it. */
#ifndef RT_FARM_INTERNAL_H
#define RT_FARM_INTERNAL_H

#include <pthread.h>

#include "assemble.h"
#include "held.h"
#include "ledger.h"
#include "farm.h"
#include "sysinfo.h"

/* start.c: the signal handlers. */
void rt_farm_signals_install(void);
/* Stops the render as a signal would (rank 0 asked this worker to stop). */
void rt_farm_stop_raise(int sig);
#define RT_FARM_STOPPED() (*rt_farm_stop_flag())

/* place.c: this rank's CPUs (before MPI), then which ranks of its node
 * share the very same mask (after MPI_Init; no-op without MPI). */
void rt_farm_place_init(rt_farm *f);
void rt_farm_place_share(rt_farm *f);

/* units.c: runs every unit of src: rendered (rt_render_stream), or, with
 * job->empty_units, handed to done as zero sums without rendering (a
 * benchmark of the farm itself). A status. */
int rt_farm_run_units(const rt_farm_job *job, const rt_render_source *src);
/* A unit's place in a rank's busy time and trace: units overlap in a
 * stream, so each counts from when it was taken or the previous unit was
 * done, whichever is later, and every moment counts once. *last is when
 * the previous unit was done; it becomes end. */
double rt_farm_unit_start(double taken, double *last, double end);

/* root.c: rank 0's state, shared by its render thread and its main thread
 * (the server). Everything in it is guarded by mu. */
typedef struct rt_root {
    pthread_mutex_t mu;
    const rt_farm_job *job;
    rt_assembly as;
    rt_ledger led;
    double t0;        /* the render's time origin */
    double last_save; /* when hooks.save last ran */
    uint32_t previewed; /* the last pass hooks.pass was called for */
    int serial;       /* no server: the render loop calls the hooks itself */
    int error;        /* a status: rendering on rank 0 failed */
} rt_root;

/* The next unit for rank (0 when none is left to hand out, or stopping). */
int rt_root_take(rt_root *R, int rank, rt_unit *u);
/* Main thread: saves now (hooks.save); whether it did. */
int rt_root_save_now(rt_root *R);
/* Main thread: progress, previews and periodic saves, as due. */
void rt_root_tick(rt_root *R);

#ifdef RT_HAVE_MPI
/* server.c: rank 0's main thread hands out units and takes in results
 * until every rank is done (returns early on a signal). */
void rt_farm_serve(rt_farm *f, rt_root *R, rt_farm_result *res);
/* worker.c: a rank other than 0 renders the units rank 0 sends. */
void rt_farm_work(rt_farm *f, const rt_farm_job *job, rt_rank_stats *me, double t0);
#endif

#endif
