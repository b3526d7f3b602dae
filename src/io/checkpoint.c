/* checkpoint.c - checkpoint file format (little endian throughout):
 *   "RTCKPT\0\0" | u32 version | u32 width height samples max_depth diffuse
 *   exact | u64 seed scene_hash | u32 sampling sampler roulette aov |
 *   u64 noise threshold (IEEE double bits) | u32 light | u32 frame job
 *   first last step | u32 frames held n | u32 turntable-frames | u64
 *   turntable degrees (IEEE double bits) | u32 rows with samples |
 *   n u32 frame numbers (one image: 0) | n x height u32 sample counts (a
 *   frame's rows, then the next frame's) | for each row with samples,
 *   width*ch i64 sums (ch: the job's layout, job.h) |
 *   u64 FNV-1a of all before. */
#include "checkpoint.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fileio.h"
#include "hash.h"
#include "status.h"

static const uint8_t MAGIC[8] = {'R', 'T', 'C', 'K', 'P', 'T', 0, 0};
#define HEADER_BYTES (8 + 4 + 6 * 4 + 2 * 8 + 4 * 4 + 8 + 4 + 6 * 4 + 8 + 4)
#define FRAME_AT 68 /* the frame job's fields, from the version on */

typedef struct hwriter {
    FILE *fp;
    uint64_t h;
    int err;
} hwriter;

static void put(hwriter *w, const void *p, size_t n)
{
    if (w->err)
        return;
    w->h = rt_hash_bytes(w->h, p, n);
    if (fwrite(p, 1, n, w->fp) != n)
        w->err = rt_status_from_errno(errno);
}
static void put_u32(hwriter *w, uint32_t v)
{
    uint8_t b[4];
    for (int i = 0; i < 4; i++)
        b[i] = (uint8_t)(v >> (8 * i));
    put(w, b, 4);
}
static void put_u64(hwriter *w, uint64_t v)
{
    uint8_t b[8];
    for (int i = 0; i < 8; i++)
        b[i] = (uint8_t)(v >> (8 * i));
    put(w, b, 8);
}

static uint64_t threshold_bits(double v)
{
    uint64_t b;
    memcpy(&b, &v, sizeof b);
    return b;
}

int rt_ckpt_write(const char *path, const rt_ckpt_id *id, const uint32_t *committed, const int64_t *acc)
{
    const int64_t *const one[1] = {acc};
    return rt_ckpt_write_frames(path, id, 1, &id->frame, committed, one);
}

int rt_ckpt_write_frames(const char *path, const rt_ckpt_id *id, uint32_t n, const uint32_t *frames,
                         const uint32_t *committed, const int64_t *const *acc)
{
    if (n > RT_CKPT_MAX_FRAMES)
        return RT_EINVAL;
    rt_atomic_file f;
    int st = rt_atomic_open(&f, path);
    if (st)
        return st;
    hwriter w = {f.fp, RT_HASH_INIT, 0};
    const uint32_t H = id->job.height;
    const size_t rows = (size_t)n * H;
    uint32_t done = 0;
    for (size_t y = 0; y < rows; y++)
        done += committed[y] != 0;
    put(&w, MAGIC, 8);
    put_u32(&w, RT_CKPT_VERSION);
    put_u32(&w, id->job.width);
    put_u32(&w, id->job.height);
    put_u32(&w, id->job.samples);
    put_u32(&w, id->job.max_depth);
    put_u32(&w, id->job.diffuse);
    put_u32(&w, id->exact);
    put_u64(&w, id->job.seed);
    put_u64(&w, id->scene_hash);
    put_u32(&w, id->sampling);
    put_u32(&w, id->job.sampler);
    put_u32(&w, (uint32_t)id->job.roulette);
    put_u32(&w, id->job.aov);
    put_u64(&w, threshold_bits(id->job.noise_threshold));
    put_u32(&w, id->job.light);
    put_u32(&w, id->frame_job);
    put_u32(&w, id->first);
    put_u32(&w, id->last);
    put_u32(&w, id->step);
    put_u32(&w, n);
    put_u32(&w, id->turn_frames);
    put_u64(&w, threshold_bits(id->turn_degrees));
    put_u32(&w, done);
    for (uint32_t i = 0; i < n; i++)
        put_u32(&w, frames[i]);
    for (size_t y = 0; y < rows; y++)
        put_u32(&w, committed[y]);
    size_t rowlen = (size_t)id->job.width * rt_job_layout(&id->job).ch;
    uint8_t *buf = malloc(rowlen * 8);
    if (!buf) {
        rt_atomic_abort(&f);
        return RT_ENOMEM;
    }
    for (size_t y = 0; y < rows && !w.err; y++) {
        if (!committed[y])
            continue;
        const int64_t *row = acc[y / H] + (y % H) * rowlen;
        for (size_t i = 0; i < rowlen; i++)
            for (int k = 0; k < 8; k++)
                buf[i * 8 + k] = (uint8_t)((uint64_t)row[i] >> (8 * k));
        put(&w, buf, rowlen * 8);
    }
    free(buf);
    uint64_t sum = w.h;
    put_u64(&w, sum);
    if (w.err) {
        rt_atomic_abort(&f);
        return w.err;
    }
    return rt_atomic_commit(&f);
}

static uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static uint64_t get_u64(const uint8_t *p) { return (uint64_t)get_u32(p) | (uint64_t)get_u32(p + 4) << 32; }

/* Reads the file at path whole and checks what every checkpoint has: the
 * magic, the checksum, the version. */
static int load(const char *path, uint8_t **out, size_t *n, char *why, size_t whylen)
{
    why[0] = 0;
    char *raw;
    size_t len;
    int st = rt_file_read_all(path, (size_t)-1 / 2, &raw, &len);
    if (st == RT_EIO)
        snprintf(why, whylen, "%s", strerror(errno));
    if (st)
        return st;
    uint8_t *data = (uint8_t *)raw;
    if (len < 8 || memcmp(data, MAGIC, 8) != 0) {
        snprintf(why, whylen, "not an rt-mpi checkpoint");
        st = RT_EFORMAT;
    } else if (len < HEADER_BYTES + 8 || get_u64(data + len - 8) != rt_hash_bytes(RT_HASH_INIT, data, len - 8)) {
        snprintf(why, whylen, "checksum mismatch: the file is corrupt or truncated");
        st = RT_ECHECKSUM;
    } else if (get_u32(data + 8) != RT_CKPT_VERSION) {
        snprintf(why, whylen, "format version %u, expected %u", get_u32(data + 8), RT_CKPT_VERSION);
        st = RT_EVERSION;
    }
    if (st) {
        free(data);
        return st;
    }
    *out = data;
    *n = len;
    return RT_OK;
}

/* The header at p (after the version) against expect. */
static int same_job(const uint8_t *p, const rt_ckpt_id *expect, char *why, size_t whylen)
{
    const uint8_t *fr = p + FRAME_AT;
    struct {
        const char *name;
        uint64_t got, want;
    } fields[] = {
        {"width", get_u32(p), expect->job.width},
        {"height", get_u32(p + 4), expect->job.height},
        {"samples", get_u32(p + 8), expect->job.samples},
        {"max depth", get_u32(p + 12), expect->job.max_depth},
        {"diffuse model", get_u32(p + 16), expect->job.diffuse},
        {"intersector", get_u32(p + 20), expect->exact},
        {"seed", get_u64(p + 24), expect->job.seed},
        {"scene", get_u64(p + 32), expect->scene_hash},
        {"sampling version", get_u32(p + 40), expect->sampling},
        {"sampler", get_u32(p + 44), expect->job.sampler},
        {"roulette", get_u32(p + 48), (uint32_t)expect->job.roulette},
        {"denoiser buffers (--aov)", get_u32(p + 52), expect->job.aov},
        {"noise threshold (bits)", get_u64(p + 56), threshold_bits(expect->job.noise_threshold)},
        {"light sampling (0 on, 1 off)", get_u32(p + 64), expect->job.light},
        {"frame job (--frames, --frame)", get_u32(fr), expect->frame_job},
        {"first frame", get_u32(fr + 4), expect->first},
        {"last frame", get_u32(fr + 8), expect->last},
        {"frame step", get_u32(fr + 12), expect->step},
        {"turntable frames", get_u32(fr + 20), expect->turn_frames},
        {"turntable degrees (bits)", get_u64(fr + 24), threshold_bits(expect->turn_degrees)},
    };
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++) {
        if (fields[i].got != fields[i].want) {
            snprintf(why, whylen, "it belongs to a different job (%s %llu, this job has %llu)", fields[i].name,
                     (unsigned long long)fields[i].got, (unsigned long long)fields[i].want);
            return RT_EMISMATCH;
        }
    }
    return RT_OK;
}

int rt_ckpt_check(const char *path, const rt_ckpt_id *expect, char *why, size_t whylen)
{
    uint8_t *data;
    size_t len;
    int st = load(path, &data, &len, why, whylen);
    if (st)
        return st;
    st = same_job(data + 12, expect, why, whylen);
    free(data);
    return st;
}

int rt_ckpt_frames(const char *path, uint32_t *n, uint32_t *frames, uint32_t max, char *why, size_t whylen)
{
    uint8_t *data;
    size_t len;
    int st = load(path, &data, &len, why, whylen);
    if (st)
        return st;
    const uint8_t *p = data + 12 + FRAME_AT;
    *n = get_u32(p + 16);
    if (*n > max || *n > RT_CKPT_MAX_FRAMES || len < HEADER_BYTES + 8 + (size_t)*n * 4) {
        snprintf(why, whylen, "inconsistent frame records");
        free(data);
        return RT_EFORMAT;
    }
    for (uint32_t i = 0; i < *n; i++)
        frames[i] = get_u32(p + 36 + 4 * (size_t)i);
    free(data);
    return RT_OK;
}

int rt_ckpt_read(const char *path, const rt_ckpt_id *expect, uint32_t *committed, int64_t *acc,
                 uint32_t *rows_done, char *why, size_t whylen)
{
    int64_t *const one[1] = {acc};
    return rt_ckpt_read_frames(path, expect, 1, committed, one, rows_done, why, whylen);
}

int rt_ckpt_read_frames(const char *path, const rt_ckpt_id *expect, uint32_t n, uint32_t *committed,
                        int64_t *const *acc, uint32_t *rows_done, char *why, size_t whylen)
{
    uint8_t *data;
    size_t len;
    int st = load(path, &data, &len, why, whylen);
    if (st)
        return st;
    const uint8_t *p = data + 12;
    if ((st = same_job(p, expect, why, whylen)) != RT_OK) {
        free(data);
        return st;
    }
    const uint32_t H = expect->job.height;
    const size_t rows = (size_t)n * H;
    uint32_t with = get_u32(p + FRAME_AT + 32);
    const uint8_t *counts = p + FRAME_AT + 36 + 4 * (size_t)n;
    size_t rowlen = (size_t)expect->job.width * rt_job_layout(&expect->job).ch;
    size_t want_len = HEADER_BYTES + (size_t)n * 4 + rows * 4 + (size_t)with * rowlen * 8 + 8;
    uint32_t counted = 0, bad = get_u32(p + FRAME_AT + 16) != n;
    if (len == want_len && !bad) {
        for (size_t y = 0; y < rows; y++) {
            uint32_t c = get_u32(counts + 4 * y);
            counted += c != 0;
            bad += c > expect->job.samples;
        }
    }
    if (len != want_len || counted != with || bad) {
        snprintf(why, whylen, "inconsistent row records");
        free(data);
        return RT_EFORMAT;
    }
    const uint8_t *q = counts + 4 * rows;
    uint32_t complete = 0;
    for (size_t y = 0; y < rows; y++) {
        int64_t *row = acc[y / H] + (y % H) * rowlen;
        committed[y] = get_u32(counts + 4 * y);
        complete += committed[y] == expect->job.samples;
        if (!committed[y]) {
            memset(row, 0, rowlen * sizeof *row);
            continue;
        }
        for (size_t i = 0; i < rowlen; i++, q += 8)
            row[i] = (int64_t)get_u64(q);
    }
    *rows_done = complete;
    free(data);
    return RT_OK;
}
