/* schedule.c - building and tracking work units. */
#include "schedule.h"

#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "status.h"

static int push(rt_sched *s, size_t *cap, rt_unit u)
{
    int st = rt_array_reserve((void **)&s->units, cap, (size_t)s->n_units + 1, sizeof u);
    if (st)
        return st;
    u.id = s->n_units;
    s->units[s->n_units++] = u;
    return RT_OK;
}

uint32_t rt_sched_pass_end(const rt_sched *s, uint32_t k)
{
    return (uint32_t)((uint64_t)s->samples * (k + 1) / s->passes);
}

typedef struct band {
    uint32_t y0, y1, c; /* rows and the samples they already have */
} band;

int rt_sched_init(rt_sched *s, const rt_job *job, const rt_sched_params *p, const uint32_t *committed)
{
    memset(s, 0, sizeof *s);
    if (!job->width || !job->height || !job->samples || !p->ranks)
        return RT_EINVAL;
    s->width = job->width;
    s->height = job->height;
    s->samples = job->samples;
    s->passes = p->passes < 1 ? 1 : p->passes > job->samples ? job->samples : p->passes;
    s->frame_rows = p->frame_rows && job->height % p->frame_rows == 0 ? p->frame_rows : 0;
    s->frames = s->frame_rows ? job->height / s->frame_rows : 1;
    s->cap = s->frame_rows ? p->frames_cap : 0;
    s->committed = calloc(job->height, sizeof *s->committed);
    s->frame_done = calloc(s->frames, sizeof *s->frame_done);
    s->released = calloc(s->frames, sizeof *s->released);
    if (!s->committed || !s->frame_done || !s->released) {
        rt_sched_free(s);
        return RT_ENOMEM;
    }
    uint32_t todo = 0;
    for (uint32_t y = 0; y < job->height; y++) {
        uint32_t c = committed ? committed[y] : 0;
        s->committed[y] = c < job->samples ? c : job->samples;
        if (s->committed[y] == job->samples) {
            s->rows_done++;
            s->frame_done[rt_sched_frame(s, y)]++;
        } else {
            todo++;
        }
    }

    uint32_t max_band = p->band ? p->band : (p->max_band ? p->max_band : 16);
    uint64_t want = (uint64_t)p->ranks * (p->units_per_rank ? p->units_per_rank : 8);
    uint32_t min_s = p->min_samples ? p->min_samples : 1;

    /* When even one-row bands are too few: column tiles, or (too narrow,
     * or asked for) sample ranges inside a pass. */
    uint32_t splits = 1, tiles = 1;
    uint32_t pass_len = job->samples / s->passes;
    if (todo > 0 && (uint64_t)todo < want) {
        uint64_t k = (want + todo - 1) / todo;
        uint64_t cmax = job->width / (p->min_cols ? p->min_cols : 16);
        uint64_t kmax = pass_len / min_s;
        if (cmax < 1)
            cmax = 1;
        if (kmax < 1)
            kmax = 1;
        if (p->split == RT_SPLIT_COLUMNS && k <= cmax)
            tiles = (uint32_t)k;
        else
            splits = (uint32_t)(k < kmax ? k : kmax);
    }

    /* One row partition, reused by every pass: runs of rows that have the
     * same committed count, cut into bands of guided (or fixed) height. */
    band *bands = NULL;
    uint32_t nb = 0, remaining = todo;
    size_t capb = 0;
    int st = RT_OK;
    for (uint32_t y = 0; y < job->height && !st;) {
        uint32_t c = s->committed[y];
        if (c == job->samples) {
            y++;
            continue;
        }
        uint32_t rows = max_band;
        if (!p->band) {
            uint64_t g = (uint64_t)remaining / (2 * want / ((uint64_t)splits * tiles) + 1);
            rows = g < 1 ? 1 : g > max_band ? max_band : (uint32_t)g;
        }
        /* a band ends at its frame's last row */
        const uint32_t end = s->frame_rows ? (y / s->frame_rows + 1) * s->frame_rows : job->height;
        uint32_t y1 = y;
        while (y1 < end && y1 - y < rows && s->committed[y1] == c)
            y1++;
        if ((st = rt_array_reserve((void **)&bands, &capb, (size_t)nb + 1, sizeof *bands)) != RT_OK)
            break;
        bands[nb++] = (band){y, y1, c};
        remaining -= y1 - y;
        y = y1;
    }
    size_t capu = 0;
    for (uint32_t k = 0; k < s->passes && !st; k++) {
        uint32_t p0 = k ? rt_sched_pass_end(s, k - 1) : 0, p1 = rt_sched_pass_end(s, k);
        for (uint32_t b = 0; b < nb && !st; b++) {
            uint32_t lo = bands[b].c > p0 ? bands[b].c : p0;
            if (lo >= p1)
                continue;
            for (uint32_t t = 0; t < tiles && !st; t++) {
                uint32_t x0 = (uint32_t)((uint64_t)job->width * t / tiles);
                uint32_t x1 = (uint32_t)((uint64_t)job->width * (t + 1) / tiles);
                for (uint32_t j = 0; j < splits && !st; j++) {
                    uint32_t s0 = lo + (uint32_t)((uint64_t)(p1 - lo) * j / splits);
                    uint32_t s1 = lo + (uint32_t)((uint64_t)(p1 - lo) * (j + 1) / splits);
                    if (s1 > s0)
                        st = push(s, &capu,
                                  (rt_unit){.y0 = bands[b].y0, .y1 = bands[b].y1, .s0 = s0, .s1 = s1, .x0 = x0,
                                            .x1 = x1});
                }
            }
        }
    }
    free(bands);
    if (st)
        rt_sched_free(s);
    return st;
}

void rt_sched_free(rt_sched *s)
{
    free(s->units);
    free(s->committed);
    free(s->frame_done);
    free(s->released);
    memset(s, 0, sizeof *s);
}

int rt_sched_next(rt_sched *s, rt_unit *u)
{
    if (s->next >= s->n_units)
        return 0;
    *u = s->units[s->next++];
    return 1;
}

const rt_unit *rt_sched_unit(const rt_sched *s, uint32_t id) { return id < s->n_units ? &s->units[id] : NULL; }

int rt_sched_can_commit(const rt_sched *s, const rt_unit *u) { return s->committed[u->y0] == u->s0; }

uint32_t rt_sched_commit(rt_sched *s, const rt_unit *u)
{
    uint32_t completed = 0;
    for (uint32_t y = u->y0; y < u->y1; y++) {
        s->committed[y] = u->s1;
        if (u->s1 == s->samples)
            completed++;
    }
    s->rows_done += completed;
    s->frame_done[rt_sched_frame(s, u->y0)] += completed; /* u never crosses a frame */

    return completed;
}

int rt_sched_ready(const rt_sched *s, const rt_unit *u)
{
    return !s->cap || rt_sched_frame(s, u->y0) < s->low + s->cap;
}

void rt_sched_release(rt_sched *s, uint32_t k)
{
    if (k >= s->frames || !rt_sched_frame_complete(s, k))
        return;
    s->released[k] = 1;
    while (s->low < s->frames && s->released[s->low])
        s->low++;
}

int rt_sched_frame_complete(const rt_sched *s, uint32_t k)
{
    return k < s->frames && s->frame_done[k] == (s->frame_rows ? s->frame_rows : s->height);
}

uint32_t rt_sched_min_committed(const rt_sched *s)
{
    uint32_t m = s->samples;
    for (uint32_t y = 0; y < s->height; y++)
        if (s->committed[y] < m)
            m = s->committed[y];
    return m;
}
