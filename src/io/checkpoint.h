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

#define RT_CKPT_VERSION 7u /* 6: the light sampling mode (rt_job.light); 7: frame jobs */

/* Everything that changes a pixel: the job, and what else decides its
 * samples' bits. */
typedef struct rt_ckpt_id {
    rt_job job;
    uint32_t exact;      /* 0 only for the Embree intersector */
    uint64_t scene_hash; /* the broadcast scene's bytes */
    uint32_t sampling;   /* RT_RENDER_SAMPLING of the build */
    /* A frame job (issue 37): its range and turntable, and the frame whose
     * sums the file holds; all 0 for a single image. */
    uint32_t frame_job, first, last, step, frame, turn_frames;
    double turn_degrees;
} rt_ckpt_id;

/* committed: per row, the samples [0, committed) its sums cover; acc:
 * width*height*ch sums (the job's layout), of which rows with committed > 0 are stored. */
int rt_ckpt_write(const char *path, const rt_ckpt_id *id, const uint32_t *committed, const int64_t *acc);

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
/* The frame whose sums the checkpoint at path holds (a frame job's), or a
 * status as rt_ckpt_read's (why filled). */
int rt_ckpt_frame(const char *path, uint32_t *frame, char *why, size_t whylen);

#endif
