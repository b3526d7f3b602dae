/* checkpoint.h - the resumable state of a render: which rows are complete
 * and their fixed-point sums, with a header that identifies the job and a
 * checksum over everything. Written atomically (temp file, fsync, rename).
 *
 * Because sums are exact integers, a resumed run adds the missing rows to
 * the restored ones and produces the same bytes as an uninterrupted run. */
#ifndef RT_CHECKPOINT_H
#define RT_CHECKPOINT_H

#include <stddef.h>
#include <stdint.h>

#define RT_CKPT_VERSION 1u

/* Everything that changes a pixel. */
typedef struct rt_ckpt_job {
    uint32_t width, height, samples, max_depth;
    uint32_t diffuse, exact; /* exact = 0 only for the Embree intersector */
    uint64_t seed, scene_hash;
} rt_ckpt_job;

/* row_done: height bytes (non-zero = complete); acc: width*height*3 sums, of
 * which only complete rows are stored. */
int rt_ckpt_write(const char *path, const rt_ckpt_job *job, const uint8_t *row_done, const int64_t *acc);

/* Loads a checkpoint for `expect`. Fills row_done and the sums of complete
 * rows (other rows of acc are zeroed). On RT_EMISMATCH, `why` names the
 * field that differs; RT_ECHECKSUM for corrupt or truncated files, RT_EFORMAT
 * for files that are not checkpoints, RT_EIO when it cannot be read. */
int rt_ckpt_read(const char *path, const rt_ckpt_job *expect, uint8_t *row_done, int64_t *acc,
                 uint32_t *rows_done, char *why, size_t whylen);

#endif
