/* ledger.h - rank 0's book of who holds which unit: queued, assigned to a
 * rank, done there (reported, its sums still held by the rank), or in the
 * image. New units go out with affinity: the schedule's runs of a band's
 * consecutive sample ranges in one pass (groups) stay with the rank that
 * started them where they can, so that the rank adds them into one held
 * piece (held.h) and sends the band's sums once, not once per range: a
 * rank first continues its last group, then starts a group nobody has
 * started, then takes the next range of any group (the job's tail). When a rank is lost, every unit it assigned or held goes back to
 * the queue, ahead of the units never handed out, and whatever the lost
 * rank sends later is refused (its owner check fails), so each unit's sums
 * enter the image exactly once. No MPI, no threads (the caller locks);
 * tests/unit/test_ledger.c drives it. */
#ifndef RT_LEDGER_H
#define RT_LEDGER_H

#include <stddef.h>
#include <stdint.h>

#include "schedule.h"

enum { RT_UNIT_QUEUED, RT_UNIT_ASSIGNED, RT_UNIT_DONE, RT_UNIT_IN };

typedef struct rt_ledger {
    uint32_t n;        /* units */
    uint8_t *state;    /* RT_UNIT_* per unit */
    int32_t *owner;    /* rank per unit (assigned or done) */
    uint32_t *pass;    /* progressive pass per unit */
    uint32_t *requeue; /* units given back by lost ranks, handed out first */
    size_t n_requeue, cap_requeue;
    int ranks;
    uint32_t *assigned; /* per rank */
    uint32_t *held;     /* per rank: done, sums not yet in */
    uint32_t passes;
    uint32_t *pass_left; /* per pass: units not yet done */
    uint32_t frames;      /* a frame job's frames (1 for one image) */
    uint32_t *frame_left; /* per frame: units not yet done */
    uint32_t *frame;      /* frame per unit */
    /* groups (units gfirst[g] .. + glen[g] in schedule order), how many of
     * each are handed out, the first group perhaps untouched, the first
     * perhaps with units left, and each rank's last group (-1: none) */
    uint32_t *gfirst, *glen, *gnext;
    uint32_t n_groups, fresh, any;
    int32_t *cur;
} rt_ledger;

/* Every unit of s starts queued. */
int rt_ledger_init(rt_ledger *L, const rt_sched *s, int ranks);
void rt_ledger_free(rt_ledger *L);

/* The next unit for rank: a requeued one, else a new one by affinity
 * (above). 1; 0 when there is none left; -1 when the units left are not
 * ready yet (a frame job's cap, rt_sched_ready: they are once an earlier
 * frame completes). */
int rt_ledger_take(rt_ledger *L, rt_sched *s, int rank, rt_unit *u);
/* 1 when rt_ledger_take would say -1 for rank now (none ready yet); it
 * changes only when a frame is released or units are requeued. */
int rt_ledger_waiting(rt_ledger *L, const rt_sched *s, int rank);
/* rank reports unit id done: 1, or 0 when the unit is not assigned to it
 * (a report of a lost rank, or a bad id). */
int rt_ledger_done(rt_ledger *L, int rank, uint32_t id);
/* rank sent the sums of unit id: 1, or 0 when it does not hold them. */
int rt_ledger_in(rt_ledger *L, int rank, uint32_t id);
/* The sum of per_unit[id] over the units rank reported done but whose
 * sums are not in (what losing it now would throw away). */
double rt_ledger_held_sum(const rt_ledger *L, int rank, const double *per_unit);
/* rank is lost: its assigned and held units are queued again. Returns how
 * many. */
uint32_t rt_ledger_lose(rt_ledger *L, int rank);
/* Every unit of pass k (0-based) is done or in. */
int rt_ledger_pass_done(const rt_ledger *L, uint32_t k);
/* Every unit of frame k is done or in. */
int rt_ledger_frame_done(const rt_ledger *L, uint32_t k);

#endif
