/* farm.h - the only module that talks MPI. Rank 0 serves work units (row
 * bands) on demand and gathers their fixed-point sums; every rank renders.
 * Built without MPI (RT_HAVE_MPI undefined) the same calls run a single
 * process. Like main, this layer may print errors and abort the job. */
#ifndef RT_FARM_H
#define RT_FARM_H

#include <stddef.h>
#include <stdint.h>

#include "progress.h"
#include "render.h"

typedef struct rt_farm {
    int rank, size;
    int local_rank, local_size; /* ranks on this node */
    int mpi;                    /* 1 when MPI is initialised */
} rt_farm;

typedef struct rt_rank_stats {
    uint64_t units, rows, segments;
    double busy; /* seconds spent rendering */
    double maxrss_mb;
} rt_rank_stats;

typedef struct rt_farm_job {
    const rt_renderer *renderer;
    uint32_t band;   /* rows per unit */
    int threads;     /* OpenMP threads of this rank */
    int prefetch;    /* units a worker keeps in flight */
    rt_progress *progress;
} rt_farm_job;

typedef struct rt_farm_result {
    int64_t *acc;          /* rank 0: width*height*3 sums (caller frees) */
    uint64_t segments;     /* total ray segments, all ranks */
    uint32_t units;        /* number of work units */
    rt_rank_stats *ranks;  /* rank 0: one entry per rank (caller frees) */
    double wall;           /* seconds spent in rt_farm_render */
} rt_farm_result;

/* Initialises MPI (thread level FUNNELED: only the main thread calls MPI). */
int rt_farm_init(rt_farm *f, int *argc, char ***argv);
void rt_farm_finalize(rt_farm *f);
/* Prints "rt-mpi: error: [rank N: ]msg" and ends every rank with code. */
void rt_farm_fail(const rt_farm *f, int code, const char *fmt, ...) __attribute__((noreturn, format(printf, 3, 4)));

/* Rank 0's value of *v on every rank. */
void rt_farm_bcast_int(const rt_farm *f, int *v);
/* Rank 0's buffer on every rank; others get a malloc'd copy. */
int rt_farm_bcast_bytes(const rt_farm *f, uint8_t **buf, size_t *len);

/* Threads for -j 0: the cores this rank may run on; when several ranks of
 * this node share the same unrestricted set, it is divided among them. */
int rt_farm_default_threads(const rt_farm *f);

/* Renders the whole image. Collective. */
int rt_farm_render(const rt_farm *f, const rt_farm_job *job, rt_farm_result *res);

#endif
