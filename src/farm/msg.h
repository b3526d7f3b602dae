/* msg.h - the farm's wire (MPI builds only): the message tags, what each
 * carries, and the polling every MPI loop of the farm uses.
 *   HELLO  worker -> 0: int32, how many units it wants in flight
 *   UNIT   0 -> worker: uint32 x 5, the unit (id, y0, y1, s0, s1)
 *   DONE   0 -> worker: empty, no more units
 *   RESULT worker -> 0: int64 x (RT_MSG_HDR + sums): unit id, segments,
 *          start and end ns (worker clock since the common start), sums */
#ifndef RT_FARM_MSG_H
#define RT_FARM_MSG_H

#include <mpi.h>

#include "internal.h"

enum { RT_TAG_HELLO = 11, RT_TAG_UNIT = 12, RT_TAG_DONE = 13, RT_TAG_RESULT = 14 };
#define RT_MSG_HDR 4

/* Sleeps 50 us, doubling with *idle up to 1 ms: quick replies while busy,
 * next to no CPU while idle. */
void rt_msg_nap(int *idle);
/* MPI_Iprobe for any tag from source, twice (see msg.c). */
int rt_msg_probe(int source, int *flag, MPI_Status *status);
void rt_msg_send_unit(const rt_farm *f, int dest, const rt_unit *u);
void rt_msg_send_done(const rt_farm *f, int dest);

#endif
