/* checkpoint.h - the resumable state of a render: how many samples of each
 * row are summed, and those fixed-point sums, with a header that identifies the job and a
 * checksum over everything. Written atomically (temp file, fsync, rename).
 *
 * Because sums are exact integers, a resumed run adds the missing rows to
 * the restored ones and produces the same bytes as an uninterrupted run. */
#ifndef RT_CHECKPOINT_H
#define RT_CHECKPOINT_H

#include <stddef.h>
#include <stdint.h>

#include "job.h"

#define RT_CKPT_VERSION 8u /* 6: the light sampling mode (rt_job.light); 7: frame jobs; 8: several frames */
#define RT_CKPT_MAX_FRAMES 4096u /* frames a checkpoint may hold */

/* Everything that changes a pixel: the job, and what else decides its
 * samples' bits. */
typedef struct rt_ckpt_id {
    rt_job job;
    uint32_t exact;      /* 0 only for the Embree intersector */
    uint64_t scene_hash; /* the broadcast scene's bytes */
    uint32_t sampling;   /* RT_RENDER_SAMPLING of the build */
    /* A frame job (issue 37): its range and turntable; all 0 for a single
     * image. frame: the frame rt_ckpt_write saves (not the identity: the
     * frames a file holds are listed in it, rt_ckpt_frames). */
    uint32_t frame_job, first, last, step, frame, turn_frames;
    double turn_degrees;
} rt_ckpt_id;

/* committed: per row, the samples [0, committed) its sums cover; acc:
 * width*height*ch sums (the job's layout), of which rows with committed > 0 are stored. */
int rt_ckpt_write(const char *path, const rt_ckpt_id *id, const uint32_t *committed, const int64_t *acc);
/* A frame job's frames in flight: n frames (numbers frames[i]), each of
 * height rows, their counts one frame after another in committed (n x
 * height) and their sums in acc[i]. */
int rt_ckpt_write_frames(const char *path, const rt_ckpt_id *id, uint32_t n, const uint32_t *frames,
                         const uint32_t *committed, const int64_t *const *acc);

/* Loads a checkpoint for `expect`. Fills committed and the sums of the rows
 * that have samples (other rows of acc are zeroed); *rows_done counts the
 * complete rows. On RT_EMISMATCH, `why` names the
 * field that differs; RT_ECHECKSUM for corrupt or truncated files, RT_EFORMAT
 * for files that are not checkpoints, RT_EIO when it cannot be read. */
int rt_ckpt_read(const char *path, const rt_ckpt_id *expect, uint32_t *committed, int64_t *acc,
                 uint32_t *rows_done, char *why, size_t whylen);
/* Only the identity: RT_OK when the checkpoint at path belongs to `expect`,
 * else a status as rt_ckpt_read's (why filled). */
int rt_ckpt_check(const char *path, const rt_ckpt_id *expect, char *why, size_t whylen);
/* The frames whose sums the checkpoint at path holds (*n of them, their
 * numbers into frames, which has room for max), or a status as
 * rt_ckpt_read's (why filled; RT_EFORMAT for more than max). */
int rt_ckpt_frames(const char *path, uint32_t *n, uint32_t *frames, uint32_t max, char *why, size_t whylen);
/* rt_ckpt_read of a checkpoint of n frames (rt_ckpt_frames): committed gets
 * n x height counts, acc[i] frame i's sums. */
int rt_ckpt_read_frames(const char *path, const rt_ckpt_id *expect, uint32_t n, uint32_t *committed,
                        int64_t *const *acc, uint32_t *rows_done, char *why, size_t whylen);

#endif
