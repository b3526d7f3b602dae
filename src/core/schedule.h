/* schedule.h - the work-unit schedule: which (rows, samples) blocks exist,
 * which is handed out next, and how far each row's sum has been committed.
 * No MPI and no threads here: the farm calls it under its own lock.
 *
 * A unit is rows [y0, y1) x columns [x0, x1) x samples [s0, s1). Units come
 * pass by pass (one pass unless progressive), and within a pass in row
 * order, the larger first and smaller towards the end (guided scheduling),
 * so the tail of the job is made of short units that keep every rank busy.
 * When there are too few rows for the ranks, one-row bands are cut into
 * column tiles (at least min_cols wide), so that every pixel is still
 * rendered whole by one rank and its sums travel once; only when the image
 * is too narrow for that (or with RT_SPLIT_SAMPLES) into sample ranges
 * instead. A pass never has both.
 *
 * Commit order: a unit's sums are added to the image only when every sample
 * before s0 is already in for its rows (committed[y] == s0) and, for a
 * tile, when every tile of its rows and samples is in; the farm holds early
 * arrivals until then. So each row's sum always covers exactly samples
 * [0, committed[y]), which is what previews and checkpoints need. (Sums are
 * exact integers, so the order of addition never changes the image itself.)
 */
#ifndef RT_SCHEDULE_H
#define RT_SCHEDULE_H

#include <stddef.h>
#include <stdint.h>

#include "job.h"

typedef struct rt_unit {
    uint32_t id;
    uint32_t y0, y1; /* rows */
    uint32_t s0, s1; /* samples */
    uint32_t x0, x1; /* columns: the whole width unless a tile */
} rt_unit;

/* Pixels of u. */
static inline uint64_t rt_unit_pixels(const rt_unit *u) { return (uint64_t)(u->y1 - u->y0) * (u->x1 - u->x0); }

/* How rows are divided when there are fewer than the ranks want. */
enum { RT_SPLIT_COLUMNS, RT_SPLIT_SAMPLES };

/* How the job's rows and samples are cut into units. */
typedef struct rt_sched_params {
    uint32_t band;           /* fixed rows per unit; 0 = guided sizes up to max_band */
    uint32_t max_band;
    uint32_t ranks;          /* ranks that render */
    uint32_t units_per_rank; /* wanted units per rank and pass for balance */
    uint32_t min_samples;    /* smallest sample range when splitting (>= 1) */
    uint32_t passes;         /* progressive passes over the image (>= 1) */
    uint32_t min_cols;       /* narrowest column tile (0: 16) */
    int split;               /* RT_SPLIT_COLUMNS (tiles, the default) or RT_SPLIT_SAMPLES */
    /* A frame job (issue 37): the job's rows are its frames' rows one
     * after another, frame_rows each (global row y is row y % frame_rows
     * of frame y / frame_rows); no unit crosses a frame, and a unit of
     * frame k is ready (rt_sched_ready) only while every frame before
     * k - frames_cap + 1 is released (complete and its sums handed on,
     * rt_sched_release), so at most frames_cap frames have units out or
     * sums held. 0: one image / no cap. */
    uint32_t frame_rows, frames_cap;
} rt_sched_params;

typedef struct rt_sched {
    rt_unit *units;
    uint32_t n_units, next;
    uint32_t *committed; /* per row: samples [0, committed) are summed */
    uint32_t width, height, samples, passes;
    uint32_t rows_done;  /* rows with every sample committed */
    /* a frame job (rt_sched_params): rows per frame, frames, the cap, rows
     * complete per frame, which are released, and the first not released */
    uint32_t frame_rows, frames, cap;
    uint32_t *frame_done;
    uint8_t *released;
    uint32_t low;
} rt_sched;

/* Plans units for every sample not already committed (committed may be NULL:
 * nothing done yet; else one count per row, e.g. from a checkpoint). */
int rt_sched_init(rt_sched *s, const rt_job *job, const rt_sched_params *p, const uint32_t *committed);
void rt_sched_free(rt_sched *s);
/* Next unit to hand out; returns 0 when every unit has been handed out. */
int rt_sched_next(rt_sched *s, rt_unit *u);
/* Looks a unit up by id (for results coming back); NULL if unknown. */
const rt_unit *rt_sched_unit(const rt_sched *s, uint32_t id);
/* 1 when u's rows have committed exactly s0 (for a tile: its sums can be
 * added once every tile of its rows and samples is in). */
int rt_sched_can_commit(const rt_sched *s, const rt_unit *u);
/* Records u (or any block of whole rows and samples) as added; returns
 * how many rows it completed. */
uint32_t rt_sched_commit(rt_sched *s, const rt_unit *u);
/* Samples committed in every row (the image is complete up to this). */
uint32_t rt_sched_min_committed(const rt_sched *s);
/* The frame of global row y (0 for one image). */
static inline uint32_t rt_sched_frame(const rt_sched *s, uint32_t y) { return s->frame_rows ? y / s->frame_rows : 0; }
/* 1 when u may be handed out now: its frame is within the cap of the first
 * frame not released (always for one image or no cap). */
int rt_sched_ready(const rt_sched *s, const rt_unit *u);
/* Complete frame k's sums are handed on: it no longer counts in the cap. */
void rt_sched_release(rt_sched *s, uint32_t k);
/* 1 when every row of frame k has every sample. */
int rt_sched_frame_complete(const rt_sched *s, uint32_t k);
/* End of progressive pass k (sample count), for k in [0, passes). */
uint32_t rt_sched_pass_end(const rt_sched *s, uint32_t k);

#endif
