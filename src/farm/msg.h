/* msg.h - the farm's wire (MPI builds only): the message tags and what
 * each carries, and the polling every MPI loop of the farm uses. Rank 0
 * hands out units and takes in small reports; the sums come combined.
 *
 *   worker -> rank 0
 *     HOST     char: its host name (first, before HELLO)
 *     HELLO    int32: how many units it wants in flight
 *     REPORT   int64 x 4 per unit done: id, segments, start and end ns
 *              (worker clock since the common start); also its request
 *              for as many new units
 *     SUMS     int64, one or more pieces (held.h), each: y0, y1, x0, x1,
 *              s0, s1, n, n unit ids, then the sums of rows [y0, y1) and
 *              columns [x0, x1) over samples [s0, s1); each pixel at most
 *              once in a message
 *     BEAT     empty: alive, nothing else to say (a lease's worth of quiet)
 *     STOPPED  empty: stopped, every sum sent
 *     BYE      double x 4: wait s, comm s, peak MB, most MB held
 *   rank 0 -> worker
 *     UNITS    uint32 x 7 per unit: id, y0, y1, x0, x1, s0, s1
 *     IDLE     empty: no unit for you now: send what you hold
 *     FLUSH    empty: send what you hold (pass, checkpoint)
 *     STOP     empty: a signal stopped the job: send what you hold, stop
 *     FINISH   int32: every sum is in: say BYE and leave; how many ranks
 *              were lost (then nobody waits in MPI_Finalize)
 *
 * No collective runs after the render starts: a lost rank would hang it. */
#ifndef RT_FARM_MSG_H
#define RT_FARM_MSG_H

#include <mpi.h>

#include "internal.h"

enum {
    RT_TAG_HELLO = 11,
    RT_TAG_REPORT,
    RT_TAG_SUMS,
    RT_TAG_BEAT,
    RT_TAG_STOPPED,
    RT_TAG_BYE,
    RT_TAG_UNITS,
    RT_TAG_IDLE,
    RT_TAG_FLUSH,
    RT_TAG_STOP,
    RT_TAG_FINISH,
    RT_TAG_HOST,
};
#define RT_MSG_REPORT 4 /* int64 per reported unit */
#define RT_MSG_UNIT 7   /* uint32 per unit sent */
#define RT_MSG_PIECE 7  /* int64 of a piece's header before its ids */

/* Sleeps 50 us, doubling with *idle up to 1 ms: quick replies while busy,
 * next to no CPU while idle. */
void rt_msg_nap(int *idle);
/* MPI_Iprobe for any tag from source, twice (see msg.c). */
int rt_msg_probe(int source, int *flag, MPI_Status *status);

#endif
