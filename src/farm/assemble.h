/* assemble.h - rank 0's result assembly: a finished unit's sums go into the
 * image in commit order (schedule.h), early arrivals wait, progressive
 * passes are noticed, and every rank's work is accounted. No MPI, no
 * threads (the caller locks), no I/O: tests/unit/test_assemble.c drives it
 * with units in any order. */
#ifndef RT_ASSEMBLE_H
#define RT_ASSEMBLE_H

#include <stddef.h>
#include <stdint.h>

#include "farm.h"
#include "job.h"
#include "schedule.h"

typedef struct rt_assembly {
    rt_sched sched;
    size_t row;   /* values per row: width times the layout's ch (job.h) */
    int64_t *acc; /* the caller's framebuffer: height*row sums */
    struct rt_pending *pending; /* units that arrived before their predecessors */
    size_t n_pending, cap_pending;
    /* blocks of whole rows whose tiles are coming in: per first row, a list
     * (one block, or one a pass in flight), so a tile finds its block at
     * once however many rows are in flight */
    struct rt_pending **gather;
    size_t n_gather;
    uint64_t segments;
    uint32_t units_in; /* units whose sums are in the image */
    rt_rank_stats *stats; /* one per rank */
    int ranks;
    double *unit_secs;     /* per unit: how long its rendering took, once reported */
    rt_trace_event *trace; /* one per unit when tracing */
    size_t n_trace, cap_trace;
    int tracing;
    uint32_t passes_done; /* progressive passes complete */
    int pass_ready;       /* a pass completed since the flag was cleared */
    int dirty;            /* samples committed since the flag was cleared */
    /* A frame job (sched.frame_rows > 0, acc NULL): each frame's sums from
     * its first unit handed out (rt_assembly_open) until it is complete and
     * taken (rt_assembly_next_frame); at most sched.cap of them at once. */
    int64_t **facc;          /* per frame, or NULL */
    struct rt_frame_acct *fst; /* per frame: segments, units, first unit out */
    uint32_t *ready;         /* complete frames not yet taken, oldest first */
    uint32_t n_ready;
    uint32_t in_flight, in_flight_peak; /* frames with sums here */
} rt_assembly;

/* Plans the units (rt_sched_init) and sets up the accounting for `ranks`
 * ranks. acc may hold restored sums, committed their counts (or NULL). */
int rt_assembly_init(rt_assembly *a, const rt_job *job, const rt_sched_params *p, const uint32_t *committed,
                     int64_t *acc, int ranks, int tracing);
void rt_assembly_free(rt_assembly *a);

/* Unit u, rendered by rank from start to end (seconds) in segs ray
 * segments: into the rank's account and the trace. */
void rt_assembly_account(rt_assembly *a, int rank, const rt_unit *u, uint64_t segs, double start, double end);

/* The sums of a block of rows, columns and one contiguous sample range (a
 * unit, or a piece of several units a worker held, held.h), holding n_units
 * units: added now if they can be committed, with every waiting block they
 * unblock, else a copy waits. A tile (not the whole width) waits for the
 * other tiles of its rows and samples, gathered into one block of whole
 * rows. RT_ENOMEM when no copy can be kept. */
int rt_assembly_sums(rt_assembly *a, const rt_unit *block, const int64_t *sums, uint32_t n_units);

/* Both, for one unit (rank 0's own units). */
int rt_assembly_add(rt_assembly *a, int rank, const rt_unit *u, const int64_t *sums, uint64_t segs, double start,
                    double end);

/* A frame job: sets up the frames' sums; restored (one per frame, NULL
 * when none, or NULL for no frame restored): the restored frames' sums,
 * taken over (the frames already complete are ready at once). */
int rt_assembly_frames(rt_assembly *a, int64_t **restored);
/* A frame job: u is handed out at `now` (seconds): its frame's sums exist
 * from now on. RT_ENOMEM. */
int rt_assembly_open(rt_assembly *a, const rt_unit *u, double now);
/* A frame job: the oldest complete frame not yet taken: its sums (now the
 * caller's, with its stats and, when tracing, a copy of its units' events)
 * into *f at `now`; 1, or 0 when none is ready. */
int rt_assembly_next_frame(rt_assembly *a, rt_farm_frame *f, double now);
/* A frame's sums in bytes. */
size_t rt_assembly_frame_bytes(const rt_assembly *a);

/* Every unit is in the image. */
int rt_assembly_complete(const rt_assembly *a);

/* Sums in the framebuffer. */
size_t rt_assembly_len(const rt_assembly *a);

/* Adds one unit to a rank's account: units, rows (a whole row at all
 * samples counts 1), segments and busy time. */
void rt_rank_stats_add(rt_rank_stats *st, const rt_unit *u, uint32_t width, uint32_t samples, uint64_t segs,
                       double start, double end);

#endif
