/* mpi_startup.c - the farm's start-up traffic with no rt-mpi code in it: a
 * check of an MPI installation and its launcher. It does what rt-mpi's
 * ranks do with MPI before and while they render: MPI_Init_thread
 * (FUNNELED), an all-reduce, a communicator of the node's ranks and an
 * all-gather in it, a 1 MiB broadcast from rank 0, then 50 rounds in which
 * every rank asks rank 0 for work and gets 4 KiB back, and a barrier.
 * Rank 0 prints "mpi_startup: ok, N ranks". Run it many times the way the
 * jobs are launched, e.g. in a batch job
 *
 *   mpicc -O2 -o mpi_startup tools/mpi_startup.c
 *   for i in $(seq 60); do srun --mpi=pmix -N 3 --ntasks-per-node=2 ./mpi_startup || echo "run $i failed"; done
 *
 * A rank that dies here (as Open MPI 4.1.4's TCP transport sometimes made
 * one under srun on the test cluster: docs/notes/farm.md) is the MPI
 * stack's fault, not rt-mpi's. */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv)
{
    int provided, rank, size;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);

    int mine = rank, top = 0;
    MPI_Allreduce(&mine, &top, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);

    MPI_Comm node;
    int nsize = 1;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &node);
    MPI_Comm_size(node, &nsize);
    int *ranks = calloc((size_t)nsize, sizeof *ranks);
    MPI_Allgather(&rank, 1, MPI_INT, ranks, 1, MPI_INT, node);
    MPI_Comm_free(&node);

    const int big = 1 << 20, small = 4096;
    char *buf = malloc(big);
    if (!ranks || !buf)
        MPI_Abort(MPI_COMM_WORLD, 1);
    memset(buf, rank, big);
    MPI_Bcast(buf, big, MPI_BYTE, 0, MPI_COMM_WORLD);

    for (int round = 0; round < 50; round++) {
        if (rank == 0) {
            for (int k = 1; k < size; k++) {
                int ask;
                MPI_Status st;
                MPI_Recv(&ask, 1, MPI_INT, MPI_ANY_SOURCE, 1, MPI_COMM_WORLD, &st);
                MPI_Send(buf, small, MPI_BYTE, st.MPI_SOURCE, 2, MPI_COMM_WORLD);
            }
        } else {
            MPI_Send(&round, 1, MPI_INT, 0, 1, MPI_COMM_WORLD);
            MPI_Recv(buf, small, MPI_BYTE, 0, 2, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        }
    }
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0)
        printf("mpi_startup: ok, %d ranks (highest %d)\n", size, top);
    free(ranks);
    free(buf);
    MPI_Finalize();
    return 0;
}
