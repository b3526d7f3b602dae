/* report.h - run reports as JSON files: the unit timeline in Chrome's
 * trace-event format (opens in Perfetto / chrome://tracing) and a
 * machine-readable summary. Written atomically. */
#ifndef RT_REPORT_H
#define RT_REPORT_H

#include <stddef.h>
#include <stdint.h>

#include "farm.h"
#include "job.h"

typedef struct rt_run_summary {
    const rt_job *job;
    uint64_t scene_hash, image_hash;
    const char *output, *intersector;
    int ranks, threads;
    int mpi; /* MPI initialised (a launcher started the job) */
    uint32_t units, rows_restored;
    double wall, total_wall;
    uint64_t segments;
    const rt_rank_stats *per_rank;
    const rt_farm_result *farm; /* rank 0's serving, lost ranks */
} rt_run_summary;

int rt_report_trace(const char *path, const rt_trace_event *ev, size_t n, int ranks);
int rt_report_stats(const char *path, const rt_run_summary *s);

#endif
