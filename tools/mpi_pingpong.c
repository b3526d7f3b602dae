/* mpi_pingpong.c - one-way latency and bandwidth between ranks 0 and 1, for
 * the scaling model's network setting (tools/validate_scaling.sh --only
 * cluster builds it with mpicc and runs it across two test-cluster hosts).
 *
 *   mpirun -np 2 ... mpi_pingpong [REPEATS]
 *
 * Latency: half the round trip of an 8-byte ping-pong (median of REPEATS,
 * default 2000, after 200 for warm-up). Bandwidth: rank 1 sends 16 messages
 * of 4 MiB to rank 0, which answers with one byte; bytes / time (best of 5).
 * Rank 0 prints one line of JSON: {"latency_s": ..., "bandwidth_Bps": ...}. */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    if (size != 2) {
        if (!rank)
            fprintf(stderr, "mpi_pingpong: needs exactly 2 ranks\n");
        MPI_Finalize();
        return 2;
    }
    int reps = argc > 1 ? atoi(argv[1]) : 2000;
    if (reps < 10)
        reps = 10;
    int peer = 1 - rank;
    char small[8] = {0};
    double *rt = malloc(sizeof *rt * (size_t)reps);
    for (int i = -200; i < reps; i++) {
        double t0 = MPI_Wtime();
        if (!rank) {
            MPI_Send(small, 8, MPI_CHAR, peer, 1, MPI_COMM_WORLD);
            MPI_Recv(small, 8, MPI_CHAR, peer, 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        } else {
            MPI_Recv(small, 8, MPI_CHAR, peer, 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            MPI_Send(small, 8, MPI_CHAR, peer, 1, MPI_COMM_WORLD);
        }
        if (i >= 0)
            rt[i] = MPI_Wtime() - t0;
    }
    qsort(rt, (size_t)reps, sizeof *rt, cmp);
    const int big = 4 << 20, nbig = 16;
    char *buf = calloc(1, (size_t)big);
    double best = 1e30;
    for (int k = 0; k < 5; k++) {
        MPI_Barrier(MPI_COMM_WORLD);
        double t0 = MPI_Wtime();
        for (int i = 0; i < nbig; i++) {
            if (rank)
                MPI_Send(buf, big, MPI_CHAR, peer, 2, MPI_COMM_WORLD);
            else
                MPI_Recv(buf, big, MPI_CHAR, peer, 2, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        }
        if (rank)
            MPI_Recv(small, 1, MPI_CHAR, peer, 3, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        else
            MPI_Send(small, 1, MPI_CHAR, peer, 3, MPI_COMM_WORLD);
        double t = MPI_Wtime() - t0;
        if (t < best)
            best = t;
    }
    if (!rank)
        printf("{\"latency_s\": %.9g, \"latency_min_s\": %.9g, \"bandwidth_Bps\": %.6g, \"repeats\": %d}\n",
               rt[reps / 2] / 2, rt[0] / 2, (double)big * nbig / best, reps);
    free(buf);
    free(rt);
    MPI_Finalize();
    return 0;
}
