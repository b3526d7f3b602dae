/* internal.h - what the farm's files share; no other layer includes it. */
#ifndef RT_FARM_INTERNAL_H
#define RT_FARM_INTERNAL_H

#include <pthread.h>

#include "assemble.h"
#include "held.h"
#include "ledger.h"
#include "msg.h"
#include "farm.h"
#include "sysinfo.h"

/* start.c: the signal handlers. */
void rt_farm_signals_install(void);
/* Stops the render as a signal would (rank 0 asked this worker to stop). */
void rt_farm_stop_raise(int sig);
/* Every rank here before any goes on (start.c's start-up wait). */
void rt_farm_sync(const rt_farm *f);
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

/* root.c: rank 0's state (ledger, assembly, stats, error), shared by its
 * render thread and its main thread (the server). Its fields are root.c's
 * alone: every verb below takes the lock itself and takes and gives
 * values. */
typedef struct rt_root rt_root;

/* The state of job's render on `ranks` ranks (own: rank 0's part), its clock starting at t0;
 * NULL with *status set when the units cannot be planned. Free with
 * rt_root_free. */
rt_root *rt_root_new(const rt_farm_job *job, const rt_farm_rank0 *own, int ranks, double t0, int *status);
void rt_root_free(rt_root *R);
/* Units in the schedule. */
uint32_t rt_root_units(const rt_root *R);
/* Rows with every sample, and the image's rows. */
void rt_root_rows(rt_root *R, uint32_t *done, uint32_t *rows);
/* Rank 0 rendered unit u (sums, segs; start and end in seconds from t0).
 * A failure is kept as the error (rt_root_error). */
void rt_root_add(rt_root *R, const rt_unit *u, const int64_t *sums, uint64_t segs, double start, double end);
/* Rank 0's rendering failed with status: it becomes the error. */
void rt_root_fail(rt_root *R, int status);
/* Rank 0's render thread, when its take said -1: waits until it may not
 * any more (a frame released, a lost rank's units requeued), an error or
 * a stop, or rt_root_wake; no timeout, no polling. */
void rt_root_wait(rt_root *R);
/* Makes the current or next rt_root_wait return (its caller has another
 * reason to look: its own threads are leaving, a signal came). */
void rt_root_wake(rt_root *R);
/* The render is over: the per-rank stats (rank 0's peak memory and host
 * name filled in here), trace and segments move into res. */
void rt_root_finish(rt_root *R, rt_farm_result *res);
/* The next unit for rank: 1; 0 when none is left to hand out (or
 * stopping); -1 when none is ready yet (a frame job's cap: serve again
 * when a frame completes, rt_root_tick). */
int rt_root_take(rt_root *R, int rank, rt_unit *u);
/* Main thread: saves now (hooks.save); whether it did. */
int rt_root_save_now(rt_root *R);
/* Main thread: complete frames (hooks.frame), progress, previews and
 * periodic saves, as due; how many frames completed (units of later
 * frames may be ready now). */
uint32_t rt_root_tick(rt_root *R);
/* A status: rendering on rank 0 failed; *complete: every unit is in. */
int rt_root_error(rt_root *R, int *complete);
/* Units rank is assigned (not yet reported done) / done but still holds. */
uint32_t rt_root_assigned(rt_root *R, int rank);
uint32_t rt_root_held(rt_root *R, int rank);
/* A frame job: every unit of frame k is reported done. */
int rt_root_frame_done(rt_root *R, uint32_t k);
/* A frame job: most frames with sums on rank 0 at once so far. */
uint32_t rt_root_frames_peak(rt_root *R);
/* Whether pass is done and another pass follows it. */
int rt_root_pass_done(rt_root *R, uint32_t pass);
/* rank is lost at now (last heard from at heard): its units go back to
 * the queue; how many. *complete as for rt_root_error. */
uint32_t rt_root_lose(rt_root *R, int rank, double now, double heard, int *complete);
/* rank reports a unit done: RT_EINVAL when it does not hold it. */
int rt_root_report(rt_root *R, int rank, const rt_msg_report *rep);
/* What a piece of sums may hold: the image's bounds, ids, channels. */
void rt_root_bounds(rt_root *R, rt_unit *bounds, uint32_t *max_ids, size_t *ch);
/* A piece of sums from rank: RT_EFORMAT when its units are not the
 * schedule's of its block or do not cover its samples exactly, RT_EINVAL
 * when rank does not hold one of them. A failure to add it is kept as the
 * error (rt_root_error). */
int rt_root_sums(rt_root *R, int rank, const rt_msg_piece *pc);
/* rank's last words, and its node's name. */
void rt_root_bye(rt_root *R, int rank, const rt_msg_bye *b);
void rt_root_host(rt_root *R, int rank, const char *host);

#ifdef RT_HAVE_MPI
/* server.c: rank 0's main thread hands out units and takes in results
 * until every rank is done (returns early on a signal). It moves messages
 * and calls root.c's verbs; rank0.c calls it, so the arrows point one way. */
void rt_farm_serve(rt_farm *f, const rt_farm_job *job, const rt_farm_rank0 *own, rt_root *R,
                   rt_farm_result *res);
/* worker.c: a rank other than 0 renders the units rank 0 sends. */
void rt_farm_work(rt_farm *f, const rt_farm_job *job, rt_rank_stats *me, double t0);
#endif

#endif
