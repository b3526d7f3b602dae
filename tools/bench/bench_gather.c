/* bench_gather.c - rank 0's assembly of one 3840x2160 image from units
 * arriving out of order (each unit's arrival shifted by up to 16,000 places,
 * about 1,000 rows in flight), with empty sums: as column tiles (4096 ranks
 * x 16 units: 16 tiles a row, gathered into whole rows before they commit,
 * assemble.c) against whole one-row units (the same bytes). Prints the
 * best of ROUNDS (default 5) of each and what the gathering adds per tile
 * and per byte of sums: the part of rank 0's cost that the serve fit of
 * tools/validate_scaling.sh (whole-row units) does not see.
 *   bench_gather [ROUNDS] */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "assemble.h"
#include "status.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static const double *arrival; /* for by_arrival */

static int by_arrival(const void *x, const void *y)
{
    double a = arrival[*(const uint32_t *)x], b = arrival[*(const uint32_t *)y];
    return a < b ? -1 : a > b;
}

/* Seconds to assemble the image from its units in the shifted order;
 * *units gets how many. */
static double assemble_once(uint32_t ranks, uint32_t band, uint32_t *units)
{
    const rt_job job = {3840, 2160, 1000, 8, 1, RT_DIFFUSE_LAMBERTIAN, RT_SAMPLER_SOBOL, 1, 0, 0, 0, RT_LIGHT_MIS};
    const rt_sched_params p = {band, 16, ranks, 16, 1, 1, 16, RT_SPLIT_COLUMNS, 0, 0};
    int64_t *acc = calloc((size_t)job.width * job.height * 3, sizeof *acc);
    int64_t *zero = calloc((size_t)job.width * 3, sizeof *zero);
    rt_assembly a;
    if (!acc || !zero || rt_assembly_init(&a, &job, &p, NULL, acc, 1, 0) != RT_OK) {
        fprintf(stderr, "bench_gather: out of memory\n");
        exit(1);
    }
    const uint32_t n = a.sched.n_units;
    rt_unit *u = malloc(n * sizeof *u);
    uint32_t *order = malloc(n * sizeof *order);
    double *key = malloc(n * sizeof *key);
    srand(1);
    for (uint32_t k = 0; k < n; k++) {
        rt_sched_next(&a.sched, &u[k]);
        order[k] = k;
        key[k] = k + rand() % 16000;
    }
    arrival = key;
    qsort(order, n, sizeof *order, by_arrival);
    const double t0 = now();
    for (uint32_t k = 0; k < n; k++)
        if (rt_assembly_sums(&a, &u[order[k]], zero, 1) != RT_OK)
            exit(1);
    const double t = now() - t0;
    if (!rt_assembly_complete(&a))
        exit(1);
    *units = n;
    rt_assembly_free(&a);
    free(u), free(order), free(key), free(acc), free(zero);
    return t;
}

int main(int argc, char **argv)
{
    const int rounds = argc > 1 ? atoi(argv[1]) : 5;
    double tiles = 1e30, rows = 1e30;
    uint32_t nt = 0, nr = 0;
    for (int r = 0; r < rounds; r++) { /* alternating */
        double t = assemble_once(4096, 0, &nt);
        tiles = t < tiles ? t : tiles;
        t = assemble_once(64, 1, &nr);
        rows = t < rows ? t : rows;
    }
    const double bytes = 3840.0 * 2160 * 24;
    printf("bench_gather: 3840x2160, best of %d: %u tiles %.1f ms, %u whole rows %.1f ms; gathering adds "
           "%.2f us a tile, %.3f ns a byte of sums\n",
           rounds, nt, tiles * 1e3, nr, rows * 1e3, (tiles - rows) / nt * 1e6, (tiles - rows) / bytes * 1e9);
    return 0;
}
