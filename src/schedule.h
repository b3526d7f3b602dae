/* schedule.h - the work-unit schedule: which (rows, samples) blocks exist, which
 * are handed out next, and which rows are complete. No MPI and no threads
 * here: the farm calls it under its own lock.
 *
 * A unit is rows [y0, y1) x samples [s0, s1). Units come in row order, the
 * larger first and smaller towards the end (guided scheduling), so the tail
 * of a job is made of short units that keep every rank busy to the end. When
 * there are too few row bands for the ranks, bands are split into sample
 * ranges; because sums are fixed-point, the image does not depend on how. */
#ifndef RT_SCHEDULE_H
#define RT_SCHEDULE_H

#include <stddef.h>
#include <stdint.h>

typedef struct rt_unit {
    uint32_t id;
    uint32_t y0, y1; /* rows */
    uint32_t s0, s1; /* samples */
} rt_unit;

typedef struct rt_sched_params {
    uint32_t height, samples;
    uint32_t band;    /* fixed rows per unit; 0 = guided sizes up to max_band */
    uint32_t max_band;
    uint32_t ranks;   /* ranks that render */
    uint32_t units_per_rank; /* wanted units per rank for balance (>= 1) */
    uint32_t min_samples;    /* smallest sample range when splitting (>= 1) */
} rt_sched_params;

typedef struct rt_sched {
    rt_unit *units;
    uint32_t n_units, next;
    uint32_t *row_samples; /* samples finished per row */
    uint8_t *row_done;     /* 1 = complete (also rows restored from a checkpoint) */
    uint32_t rows_done, height, samples;
    uint32_t units_done;
} rt_sched;

/* Builds the units for every row not already marked in done (may be NULL:
 * nothing done yet). */
int rt_sched_init(rt_sched *s, const rt_sched_params *p, const uint8_t *done);
void rt_sched_free(rt_sched *s);
/* Next unit to hand out; returns 0 when every unit has been handed out. */
int rt_sched_next(rt_sched *s, rt_unit *u);
/* Records a finished unit; returns how many rows it completed. */
uint32_t rt_sched_complete(rt_sched *s, const rt_unit *u);
/* Looks a unit up by id (for results coming back); NULL if unknown. */
const rt_unit *rt_sched_unit(const rt_sched *s, uint32_t id);
/* Gives a handed-out unit back (its rank was lost): it will be handed out
 * again. */
int rt_sched_requeue(rt_sched *s, uint32_t id);

#endif
