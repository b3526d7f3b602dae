/* report.h - run reports as JSON files, built with cJSON: the unit
 * timeline in Chrome's trace-event format (opens in Perfetto /
 * chrome://tracing) and a machine-readable summary, both saying where they
 * come from (version, features, command line, start time, host, MPI
 * library, Slurm job). Written atomically. Any byte of a command line or
 * path gives valid JSON: invalid UTF-8 becomes U+FFFD. */
#ifndef RT_REPORT_H
#define RT_REPORT_H

#include <stddef.h>
#include <stdint.h>
#include <time.h>

#include "farm.h"
#include "job.h"

/* Where a report comes from. */
typedef struct rt_report_origin {
    int argc;
    char *const *argv;        /* the command line exactly as given */
    time_t start;             /* the run's start (written as ISO 8601, UTC) */
    const char *host;         /* rank 0's host name (every rank's is in the
                               * farm's per-rank stats) */
    const char *mpi_library;  /* rt_farm_mpi_version() */
    const char *slurm_job_id; /* SLURM_JOB_ID, or NULL outside Slurm */
} rt_report_origin;

typedef struct rt_run_summary {
    const rt_job *job;
    uint64_t scene_hash, image_hash;
    const char *output, *intersector;
    int ranks, threads;
    int mpi; /* MPI initialised (a launcher started the job) */
    uint32_t units, rows_restored;
    double wall, total_wall;
    double setup; /* rank 0: from the scene broadcast to the render's start */
    uint64_t segments;
    const rt_rank_stats *per_rank;
    rt_report_origin origin;
    const rt_farm_result *farm; /* rank 0's serving, lost ranks */
    const struct rt_spp_stats *spp; /* adaptive sampling, or NULL */
    int frame_job;  /* a frame of a frame job: its number is recorded */
    uint32_t frame;
    uint32_t frames_peak; /* frame job: frames held on rank 0 at most so far */
    double frame_start;   /* frame job: its first unit handed out, seconds
                           * from the range's start (rank 0's clock) */
} rt_run_summary;

/* Where adaptive sampling put the samples: the mean per pixel, and how
 * many pixels took each count (RT_ADAPT_FIRST << k; the last level
 * holds the pixels that took all -s). */
#define RT_SPP_LEVELS 24
typedef struct rt_spp_stats {
    double mean;
    uint32_t n_levels;
    uint32_t count[RT_SPP_LEVELS];  /* samples of level k */
    uint64_t pixels[RT_SPP_LEVELS]; /* pixels that took them */
} rt_spp_stats;

/* RT_EUNSUPPORTED in a build without cJSON (the option parser refuses
 * --stats and --trace there first). */
int rt_report_trace(const char *path, const rt_trace_event *ev, size_t n, int ranks, const rt_report_origin *origin);
int rt_report_stats(const char *path, const rt_run_summary *s);

/* The build's features, space-separated ("mpi openmp png exr json"), into
 * buf: what --version prints and --stats records. mpi_library is
 * rt_farm_mpi_version(): "none" in a build without MPI. */
void rt_report_features(char *buf, size_t n, const char *mpi_library);

/* A copy of s (malloc'd, NULL without memory) that is valid UTF-8: every
 * byte that is not part of a well-formed sequence (stray continuation
 * bytes, truncated or overlong sequences, surrogates, beyond U+10FFFF) is
 * replaced by U+FFFD. */
char *rt_report_utf8(const char *s);

#endif
