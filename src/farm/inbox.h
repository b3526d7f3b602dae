/* inbox.h - the polling every MPI loop of the farm uses (MPI builds only):
 * a probe that sees a message on its first pass, and a nap between probes. */
#ifndef RT_FARM_INBOX_H
#define RT_FARM_INBOX_H

#include <mpi.h>

/* Sleeps 50 us, doubling with *idle up to 1 ms: quick replies while busy,
 * next to no CPU while idle. */
void rt_inbox_nap(int *idle);
/* MPI_Iprobe for any tag from source, twice (see inbox.c). */
int rt_inbox_probe(int source, int *flag, MPI_Status *status);

#endif
