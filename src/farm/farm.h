/* farm.h - the only layer that talks MPI. Rank 0 builds nothing here: it
 * hands out work units on demand and gathers their fixed-point sums; every
 * rank renders. Built without MPI (RT_HAVE_MPI undefined) the same calls
 * run a single process. Like main, this layer may print errors and end the
 * job.
 *
 * What the run does with the sums while they come in (progress line,
 * previews, checkpoints) reaches the farm through hooks (rt_farm_hooks), so
 * the farm knows neither the progress display nor the checkpoint format.
 *
 * Files: start.c (MPI start-up, failure, broadcast, signals), place.c (CPU
 * masks and thread binding), root.c (rank 0: its own rendering and the
 * hooks), server.c (rank 0's MPI server), worker.c (the other ranks),
 * assemble.c (rank 0's result assembly: no MPI, unit-tested), units.c
 * (running a rank's units), msg.c (the wire's codec: no MPI, unit-tested),
 * inbox.c (polling for messages), policy.h (defaults), exitcode.h. */
#ifndef RT_FARM_H
#define RT_FARM_H

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#include "exitcode.h"
#include "policy.h"
#include "render.h"
#include "schedule.h"

/* Slots of a rank's ring of frame renderers: a slot is rebuilt for frame k
 * only once every unit of frame k - RT_FARM_RING on the rank is done, which
 * the cap guarantees (a unit of k is handed out only when frames before
 * k - cap + 1 are complete) and units.c checks. */
#define RT_FARM_RING (RT_POLICY_FRAMES_IN_FLIGHT + 2)


typedef struct rt_farm {
    int rank, size;
    int cores;      /* CPUs in this rank's affinity mask (OpenMP places when omp_bound) */
    int mask_share; /* ranks of this node with the very same mask (>= 1) */
    int mask_index; /* this rank's place among them */
    int omp_bound;  /* OpenMP binds threads to places (OMP_PROC_BIND): cores counts places */
    int mpi;        /* 1 when MPI is initialised */
    int lost;       /* rank 0: ranks lost in the render (rt_farm_render sets it) */
} rt_farm;

typedef struct rt_rank_stats {
    double units, rows, segments;
    double busy;      /* seconds rendering */
    double wait;      /* seconds with nothing to render (waiting for rank 0) */
    double comm;      /* seconds in MPI calls and message handling */
    double maxrss_mb; /* peak resident memory */
    double held_mb;   /* most sums held at once, not yet sent to rank 0 */
    int lost;         /* the rank died or stopped answering; its units went to others */
    double lost_at;   /* when rank 0 found it lost (seconds into the render) */
    double silent;    /* how long rank 0 had not heard from it then */
    double redone;    /* seconds of its rendering lost: units it reported done whose sums never came */
    uint32_t units_redone; /* its units handed to the others (done or not) */
    char host[64];    /* the node it ran on (gethostname, cut to 63 bytes) */
} rt_rank_stats;

typedef struct rt_trace_event {
    int32_t rank;
    rt_unit unit;
    double start, end; /* seconds since the render started */
} rt_trace_event;

/* A frame job's frame whose last sums are in (rt_farm_hooks.frame). */
typedef struct rt_farm_frame {
    uint32_t index;      /* among the job's frames (0-based) */
    int64_t *acc;        /* its sums, laid out as one image's; the hook's
                          * (free with rt_mem_free(acc, acc_bytes)) */
    size_t acc_bytes;
    uint64_t segments;   /* of its units */
    uint32_t units;
    double first, last;  /* seconds from the render's start: its first unit
                          * handed out, its last sums in */
    rt_trace_event *trace; /* its units' events when tracing (the hook's: free) */
    size_t n_trace;
    uint32_t in_flight;  /* frames with sums on rank 0 (this one included) */
} rt_farm_frame;

/* A consistent copy of a frame job's frames in flight, for the checkpoint. */
typedef struct rt_farm_frames {
    uint32_t n;                /* frames in flight (incomplete, with sums) */
    const uint32_t *index;     /* theirs, ascending */
    const uint32_t *committed; /* n x height counts: each frame's rows */
    int64_t *const *acc;       /* n frames of sums */
} rt_farm_frames;

/* The run's side of the hooks, defined by the program that runs the farm:
 * what the hooks read of the run and the state they update. The farm never
 * looks inside; it hands the pointer back to each hook. */
typedef struct rt_farm_client rt_farm_client;

/* What rank 0's main thread calls while the sums come in. Every hook may
 * be NULL. committed[y] counts the samples of row y in acc; both are a
 * consistent copy, valid during the call. */
typedef struct rt_farm_hooks {
    rt_farm_client *client;
    /* Often (at least once a millisecond while results arrive): the pass
     * being rendered (1-based), rows with every sample, ray segments. */
    void (*progress)(rt_farm_client *c, uint32_t pass, uint64_t rows_done, uint64_t segments);
    /* After progressive pass `pass` (1-based) of sched.passes, all but the
     * last: every row has at least `samples` samples. */
    void (*pass)(rt_farm_client *c, uint32_t pass, uint32_t samples, const uint32_t *committed, const int64_t *acc);
    /* Saves the state (a checkpoint) every save_interval seconds while new
     * samples came in, and once more when a signal stops the render.
     * Returns a status: non-zero keeps the samples marked as unsaved. */
    int (*save)(rt_farm_client *c, const uint32_t *committed, const int64_t *acc);
    double save_interval;
    /* A signal stopped the render, after the last save (saved: it
     * succeeded); the farm then ends the job with RT_EXIT_INTERRUPTED. */
    void (*stopped)(rt_farm_client *c, int sig, int saved, uint32_t rows_done, uint32_t rows);
    /* A frame job (job.frames > 0), instead of save: saves the frames in
     * flight. A status, as save's. */
    int (*save_frames)(rt_farm_client *c, const rt_farm_frames *fr);
    /* A frame job: frame f->index is complete; its sums are the hook's. In
     * frame order of completion, from rank 0's main thread. */
    void (*frame)(rt_farm_client *c, rt_farm_frame *f);
    /* A frame job: a frame's sums were allocated (its first unit is handed
     * out). Called under the farm's lock from either of rank 0's threads:
     * it must only count. */
    void (*frame_open)(rt_farm_client *c, uint32_t index);
} rt_farm_hooks;

typedef struct rt_farm_job {
    const rt_renderer *renderer; /* its job says what to render (a frame job: a frame's size) */
    /* A frame job (issue 37): frames > 0 frames of renderer's size, one
     * schedule of frames x height rows (schedule.h's frame_rows), at most
     * RT_POLICY_FRAMES_IN_FLIGHT frames with units out. Each rank renders a
     * unit of frame index k with frame_renderer(frame_ctx, slot, k, &r): the
     * renderer of frame k, built into slot `slot` of RT_FARM_RING (the
     * caller's: what it held before is no longer in use), called by the
     * thread that takes the unit. 0: one image, renderer renders it all. */
    uint32_t frames;
    int (*frame_renderer)(void *ctx, uint32_t slot, uint32_t index, const rt_renderer **r);
    void *frame_ctx;
    rt_sched_params sched;
    int threads;          /* OpenMP threads of this rank */
    int prefetch;         /* units a worker keeps in flight */
    int empty_units;      /* benchmark of the farm itself: units are not rendered */
    int root_serves_only; /* rank 0 serves and does not render (when size > 1) */
    /* Workers keep their sums and send them combined (held.h): at the
     * latest every flush_interval seconds, when they hold flush_bytes, when
     * rank 0 asks (progressive passes, checkpoints, the end) and on a
     * signal. A worker that rank 0 has not heard from for `lease` seconds
     * is lost: its units go to the others (0 bytes or lease: policy.h's
     * defaults; flush_interval RT_POLICY_FLUSH_NEVER: no timer). */
    double flush_interval;
    size_t flush_bytes;
    double lease;
} rt_farm_job;

/* What only rank 0 has: the image it gathers into and what it calls while
 * the sums come in. */
typedef struct rt_farm_rank0 {
    int64_t *acc;              /* width*height*ch sums, preloaded on resume (a frame job: NULL) */
    const uint32_t *committed; /* samples per row restored from a checkpoint, or NULL
                                * (a frame job: frames x height counts) */
    int64_t **frame_acc;       /* a frame job: per frame, its restored sums or NULL (taken over) */
    int trace;                 /* record one event per unit */
    rt_farm_hooks hooks;
} rt_farm_rank0;

typedef struct rt_farm_result {
    uint64_t segments;    /* all ranks */
    uint32_t units;       /* units rendered in this run */
    rt_rank_stats *ranks; /* rank 0: one per rank (caller frees) */
    rt_trace_event *trace;
    size_t n_trace;
    double wall; /* seconds in rt_farm_render (a frame job's frame: from its
                  * first unit handed out to its last sums in) */
    double start; /* a frame job's frame: when its first unit was handed out,
                   * seconds from the range's start on rank 0's clock */
    /* rank 0 only: */
    int lost;               /* ranks lost during the render */
    uint64_t msgs_in;       /* messages rank 0 received */
    uint64_t bytes_in;      /* bytes rank 0 received */
    double serve_cpu;       /* CPU seconds of rank 0's main thread (the server) */
    /* A frame job's cap: how often rank 0's render thread had nothing to
     * render and waited (rt_root_wait), and its CPU seconds meanwhile (the
     * seconds are ranks[0].wait) */
    uint64_t render_waits;
    double render_wait_cpu;
    double final_combine;   /* seconds from the last unit rendered to the last sums in */
} rt_farm_result;

int rt_farm_init(rt_farm *f, int *argc, char ***argv);
/* Ends MPI. After a render that lost ranks (rt_farm_result.lost) MPI
 * cannot finalize (it would wait for the dead): rank 0 ends the job with
 * MPI_Abort and status 0 instead, once the image is written. */
void rt_farm_finalize(rt_farm *f);
/* The MPI library this program was linked with (MPI_Get_library_version,
 * first line), or "none" in a build without MPI. Needs no MPI_Init. */
const char *rt_farm_mpi_version(void);
/* Prints "rt-mpi: error: [rank N: ]msg" and ends every rank with code. */
void rt_farm_fail(const rt_farm *f, rt_exit_code code, const char *fmt, ...) __attribute__((noreturn, format(printf, 3, 4)));
/* fn(ctx) runs once at the start of rt_farm_fail on this process (after
 * the message is formatted, before it is printed): rank 0's frame job
 * joins its writer thread there, so that no file is left half written.
 * NULL clears it. Set and cleared by the thread that may call
 * rt_farm_fail while it is set. */
void rt_farm_on_fail(void (*fn)(void *), void *ctx);
/* Ends the whole job with code, without a message. */
void rt_farm_exit(const rt_farm *f, rt_exit_code code) __attribute__((noreturn));

void rt_farm_bcast_int(const rt_farm *f, int *v);
/* Every rank's verdict before the render (an exit code, 0 for none):
 * returns the largest, and *root gets rank 0's. Collective. So a setting
 * only one node has wrong (its RT_ACCEL, its OMP_NUM_THREADS) stops the job
 * with that rank's own message, not a later failure elsewhere. */
int rt_farm_agree(const rt_farm *f, int mine, int *root);
int rt_farm_bcast_bytes(const rt_farm *f, uint8_t **buf, size_t *len);

/* Threads for -j 0: the cores of this rank's affinity mask, divided among
 * the ranks of the node that have the same mask (unbound ranks, or ranks in
 * one container's cpuset), so together they use each core once. */
int rt_farm_default_threads(const rt_farm *f);

/* Binds this rank's OpenMP threads (threads of them, the team the render
 * will use) one to a CPU, when they exactly fill this rank's share of its
 * affinity mask (the mask's CPUs divided among the ranks of the node that
 * have the very same mask: ranks of one thread each that fill it are bound
 * too) and the user has not set OMP_PROC_BIND. Unbound, the render's
 * threads started rendering up to 5 to 7 ms late on the development
 * machine; bound, within 0.3 ms (docs/PERFORMANCE.md). Never binds when
 * threads would have to share a CPU or could leave one idle, nor with
 * RT_BIND=0. Returns 1 when it bound them. */
int rt_farm_bind_threads(const rt_farm *f, int threads);

/* The flag the signal handlers set; give it to rt_renderer.stop. */
const volatile sig_atomic_t *rt_farm_stop_flag(void);

/* Renders the whole image (a frame job: all its frames, each handed to
 * hooks.frame as soon as it is complete, res the whole range's).
 * Collective: every rank gives the same job, rank 0 its own part too (the
 * other ranks' own is not read: NULL). Returns
 * only when every sum is in (res filled): a failure ends the job here with
 * RT_EXIT_RUNTIME, and on SIGTERM, SIGINT or SIGUSR1 rank 0 saves
 * (hooks.save), calls hooks.stopped and the job ends with
 * RT_EXIT_INTERRUPTED; so there is no status to return. */
void rt_farm_render(rt_farm *f, const rt_farm_job *job, const rt_farm_rank0 *own, rt_farm_result *res);

#endif
