/* progress.h - progress line on stderr: one updating line on a terminal,
 * a plain line every ~10 s in batch logs, nothing with --quiet. */
#ifndef RT_PROGRESS_H
#define RT_PROGRESS_H

#include <stdint.h>

typedef struct rt_progress {
    int enabled, tty;
    double t0, last;
    uint64_t total_rows;
    uint64_t base_rows; /* rows restored from a checkpoint: not part of the rate */
    int pass, passes;
    /* A frame job's line covers the whole range: rows and ray segments of
     * the earlier frames come before this frame's (0 for one image). */
    uint64_t offset_rows, offset_segments, frame_rows;
    uint32_t frame_index, frames; /* frames 0: one image */
} rt_progress;


void rt_progress_init(rt_progress *p, uint64_t total_rows, int quiet);
/* rows_done counts finished rows; segments is the running ray count. */
void rt_progress_update(rt_progress *p, uint64_t rows_done, uint64_t segments);
void rt_progress_finish(rt_progress *p, uint64_t segments);

#endif
