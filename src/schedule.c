/* schedule.c - building and tracking work units. */
#include "schedule.h"

#include <stdlib.h>
#include <string.h>

#include "status.h"

static int push(rt_unit **arr, uint32_t *n, uint32_t *cap, rt_unit u)
{
    if (*n == *cap) {
        uint32_t nc = *cap ? *cap * 2 : 256;
        rt_unit *q = realloc(*arr, (size_t)nc * sizeof *q);
        if (!q)
            return RT_ENOMEM;
        *arr = q;
        *cap = nc;
    }
    u.id = *n;
    (*arr)[(*n)++] = u;
    return RT_OK;
}

int rt_sched_init(rt_sched *s, const rt_sched_params *p, const uint8_t *done)
{
    memset(s, 0, sizeof *s);
    if (!p->height || !p->samples || !p->ranks)
        return RT_EINVAL;
    s->height = p->height;
    s->samples = p->samples;
    s->row_samples = calloc(p->height, sizeof *s->row_samples);
    s->row_done = calloc(p->height, 1);
    if (!s->row_samples || !s->row_done) {
        rt_sched_free(s);
        return RT_ENOMEM;
    }
    uint32_t todo = 0;
    for (uint32_t y = 0; y < p->height; y++) {
        if (done && done[y]) {
            s->row_done[y] = 1;
            s->row_samples[y] = p->samples;
            s->rows_done++;
        } else {
            todo++;
        }
    }
    uint32_t max_band = p->band ? p->band : (p->max_band ? p->max_band : 16);
    uint32_t per_rank = p->units_per_rank ? p->units_per_rank : 8;
    uint64_t want = (uint64_t)p->ranks * per_rank; /* units for good balance */
    uint32_t min_s = p->min_samples ? p->min_samples : 1;

    /* Sample split: when even one-row bands are too few for the ranks. */
    uint32_t splits = 1;
    if (todo > 0 && (uint64_t)todo < want) {
        uint64_t k = (want + todo - 1) / todo;
        uint64_t kmax = p->samples / min_s;
        if (kmax < 1)
            kmax = 1;
        splits = (uint32_t)(k < kmax ? k : kmax);
    }

    uint32_t cap = 0, remaining = todo;
    int st = RT_OK;
    uint32_t y = 0;
    while (y < p->height && !st) {
        if (s->row_done[y]) {
            y++;
            continue;
        }
        /* Guided: a share of what is left, at most max_band, at least 1. */
        uint32_t rows = max_band;
        if (!p->band) {
            uint64_t g = (uint64_t)remaining / (2 * want / (splits ? splits : 1) + 1);
            rows = g < 1 ? 1 : g > max_band ? max_band : (uint32_t)g;
        }
        uint32_t y1 = y;
        while (y1 < p->height && y1 - y < rows && !s->row_done[y1])
            y1++;
        for (uint32_t k = 0; k < splits && !st; k++) {
            uint32_t s0 = (uint32_t)((uint64_t)p->samples * k / splits);
            uint32_t s1 = (uint32_t)((uint64_t)p->samples * (k + 1) / splits);
            if (s1 > s0) {
                rt_unit u = {0, y, y1, s0, s1};
                st = push(&s->units, &s->n_units, &cap, u);
            }
        }
        remaining -= y1 - y;
        y = y1;
    }
    if (st)
        rt_sched_free(s);
    return st;
}

void rt_sched_free(rt_sched *s)
{
    free(s->units);
    free(s->row_samples);
    free(s->row_done);
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

uint32_t rt_sched_complete(rt_sched *s, const rt_unit *u)
{
    uint32_t completed = 0;
    s->units_done++;
    for (uint32_t y = u->y0; y < u->y1; y++) {
        s->row_samples[y] += u->s1 - u->s0;
        if (!s->row_done[y] && s->row_samples[y] >= s->samples) {
            s->row_done[y] = 1;
            completed++;
        }
    }
    s->rows_done += completed;
    return completed;
}

int rt_sched_requeue(rt_sched *s, uint32_t id)
{
    /* Swap the lost unit to just before `next` and step back over it. */
    if (id >= s->n_units || s->next == 0)
        return RT_EINVAL;
    uint32_t pos = id; /* units keep their slot: find it */
    if (s->units[pos].id != id)
        return RT_EINVAL;
    uint32_t last = --s->next;
    rt_unit tmp = s->units[last];
    s->units[last] = s->units[pos];
    s->units[pos] = tmp;
    return RT_OK;
}
