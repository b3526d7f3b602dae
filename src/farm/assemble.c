/* assemble.c - rank 0's result assembly (see assemble.h). */
#include "assemble.h"

#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "mem.h"
#include "status.h"

struct rt_frame_acct {
    uint64_t segments;
    uint32_t units;
    double first;
};

struct rt_pending {
    rt_unit unit; /* the block's rows, columns and samples */
    int64_t *sums;
    uint32_t n_units;
    uint32_t cols; /* a gathered block: columns in so far */
    struct rt_pending *next; /* a gathered block: the next of its first row */
};

int rt_assembly_init(rt_assembly *a, const rt_job *job, const rt_sched_params *p, const uint32_t *committed,
                     int64_t *acc, int ranks, int tracing)
{
    memset(a, 0, sizeof *a);
    int st = rt_sched_init(&a->sched, job, p, committed);
    if (st)
        return st;
    a->row = (size_t)job->width * rt_job_layout(job).ch;
    a->acc = acc;
    a->ranks = ranks;
    a->tracing = tracing;
    a->stats = calloc((size_t)(ranks > 0 ? ranks : 1), sizeof *a->stats);
    a->unit_secs = calloc(a->sched.n_units ? a->sched.n_units : 1, sizeof *a->unit_secs);
    a->gather = calloc(job->height, sizeof *a->gather);
    if (!a->stats || !a->unit_secs || !a->gather) {
        free(a->stats);
        free(a->unit_secs);
        free(a->gather);
        rt_sched_free(&a->sched);
        return RT_ENOMEM;
    }
    return RT_OK;
}

void rt_assembly_free(rt_assembly *a)
{
    for (size_t i = 0; i < a->n_pending; i++)
        free(a->pending[i].sums);
    free(a->pending);
    for (uint32_t y = 0; a->gather && y < a->sched.height; y++)
        for (struct rt_pending *g = a->gather[y], *next; g; g = next) {
            next = g->next;
            free(g->sums);
            free(g);
        }
    free(a->gather);
    free(a->stats);
    free(a->unit_secs);
    free(a->trace);
    for (uint32_t k = 0; a->facc && k < a->sched.frames; k++)
        rt_mem_free(a->facc[k], rt_assembly_frame_bytes(a));
    free(a->facc);
    free(a->fst);
    free(a->ready);
    rt_sched_free(&a->sched);
    memset(a, 0, sizeof *a);
}

size_t rt_assembly_frame_bytes(const rt_assembly *a)
{
    return (size_t)a->sched.frame_rows * a->row * sizeof(int64_t);
}

/* Frame k is complete: ready for rt_assembly_next_frame. */
static void frame_ready(rt_assembly *a, uint32_t k) { a->ready[a->n_ready++] = k; }

int rt_assembly_frames(rt_assembly *a, int64_t **restored)
{
    const uint32_t F = a->sched.frames;
    a->facc = calloc(F, sizeof *a->facc);
    a->fst = calloc(F, sizeof *a->fst);
    a->ready = calloc(F, sizeof *a->ready);
    if (!a->facc || !a->fst || !a->ready)
        return RT_ENOMEM;
    for (uint32_t k = 0; restored && k < F; k++) {
        if (!(a->facc[k] = restored[k]))
            continue;
        restored[k] = NULL;
        a->in_flight++;
        if (rt_sched_frame_complete(&a->sched, k))
            frame_ready(a, k);
    }
    a->in_flight_peak = a->in_flight;
    return RT_OK;
}

int rt_assembly_open(rt_assembly *a, const rt_unit *u, double now)
{
    const uint32_t k = rt_sched_frame(&a->sched, u->y0);
    if (!a->facc || a->facc[k])
        return RT_OK;
    if (!(a->facc[k] = rt_mem_zeroed(rt_assembly_frame_bytes(a))))
        return RT_ENOMEM;
    a->fst[k].first = now;
    if (++a->in_flight > a->in_flight_peak)
        a->in_flight_peak = a->in_flight;
    return RT_OK;
}

int rt_assembly_next_frame(rt_assembly *a, rt_farm_frame *f, double now)
{
    if (!a->n_ready)
        return 0;
    const uint32_t k = a->ready[0];
    memmove(a->ready, a->ready + 1, --a->n_ready * sizeof *a->ready);
    *f = (rt_farm_frame){.index = k, .acc = a->facc[k], .acc_bytes = rt_assembly_frame_bytes(a),
                         .segments = a->fst[k].segments, .units = a->fst[k].units, .first = a->fst[k].first,
                         .last = now, .in_flight = a->in_flight};
    a->facc[k] = NULL;
    a->in_flight--;
    size_t n = 0;
    for (size_t i = 0; i < a->n_trace; i++)
        n += rt_sched_frame(&a->sched, a->trace[i].unit.y0) == k;
    /* out of memory for the copy: the frame's trace misses its events */
    if (n && (f->trace = malloc(n * sizeof *f->trace)))
        for (size_t i = 0; i < a->n_trace; i++)
            if (rt_sched_frame(&a->sched, a->trace[i].unit.y0) == k)
                f->trace[f->n_trace++] = a->trace[i];
    return 1;
}

/* Where row y's sums go: the image's, or (a frame job) its frame's. */
static int64_t *row_at(const rt_assembly *a, uint32_t y)
{
    if (!a->facc)
        return a->acc + (size_t)y * a->row;
    const uint32_t H = a->sched.frame_rows;
    return a->facc[y / H] + (size_t)(y % H) * a->row;
}

size_t rt_assembly_len(const rt_assembly *a) { return (size_t)a->sched.height * a->row; }

int rt_assembly_complete(const rt_assembly *a) { return a->units_in == a->sched.n_units; }

void rt_rank_stats_add(rt_rank_stats *st, const rt_unit *u, uint32_t width, uint32_t samples, uint64_t segs,
                       double start, double end)
{
    st->units++;
    st->rows += (double)rt_unit_pixels(u) * (u->s1 - u->s0) / ((double)width * samples);
    st->segments += (double)segs;
    st->busy += end - start;
}

static size_t unit_len(const rt_assembly *a, const rt_unit *u) { return (size_t)(u->y1 - u->y0) * a->row; }

static int whole(const rt_assembly *a, const rt_unit *u) { return u->x0 == 0 && u->x1 == a->sched.width; }

static void commit(rt_assembly *a, const rt_unit *u, const int64_t *sums, uint32_t n_units)
{
    size_t n = unit_len(a, u);
    a->units_in += n_units;
    int64_t *dst = row_at(a, u->y0); /* u never crosses a frame */
    for (size_t i = 0; i < n; i++)
        dst[i] += sums[i];
    rt_sched_commit(&a->sched, u);
    a->dirty = 1;
    const uint32_t k = rt_sched_frame(&a->sched, u->y0);
    if (a->facc && rt_sched_frame_complete(&a->sched, k))
        frame_ready(a, k);
    /* A progressive pass is complete when every row has its samples (an
     * O(height) scan, so only in progressive runs). */
    const rt_sched *sc = &a->sched;
    while (sc->passes > 1 && a->passes_done < sc->passes &&
           rt_sched_min_committed(sc) >= rt_sched_pass_end(sc, a->passes_done)) {
        a->passes_done++;
        a->pass_ready = 1;
    }
}

/* Commits every waiting unit that can be, until none can: a commit may
 * unblock an entry already passed over. The list never holds more than
 * the units in flight. */
static void commit_pending(rt_assembly *a)
{
    for (size_t i = 0; i < a->n_pending;) {
        if (rt_sched_can_commit(&a->sched, &a->pending[i].unit)) {
            commit(a, &a->pending[i].unit, a->pending[i].sums, a->pending[i].n_units);
            free(a->pending[i].sums);
            a->pending[i] = a->pending[--a->n_pending];
            i = 0;
        } else {
            i++;
        }
    }
}

/* Keeps sums (the caller's, now the assembly's) until u can commit. */
static int keep_owned(rt_assembly *a, const rt_unit *u, int64_t *sums, uint32_t n_units)
{
    if (rt_array_reserve((void **)&a->pending, &a->cap_pending, a->n_pending + 1, sizeof *a->pending)) {
        free(sums);
        return RT_ENOMEM;
    }
    a->pending[a->n_pending++] = (struct rt_pending){.unit = *u, .sums = sums, .n_units = n_units};
    return RT_OK;
}

static int keep(rt_assembly *a, const rt_unit *u, const int64_t *sums, uint32_t n_units)
{
    size_t n = unit_len(a, u);
    int64_t *copy = malloc(n * sizeof *copy);
    if (!copy)
        return RT_ENOMEM;
    memcpy(copy, sums, n * sizeof *copy);
    return keep_owned(a, u, copy, n_units);
}

/* A tile: copied into the block of whole rows it belongs to (same rows and
 * samples); once every column is in, the block goes on like a unit. */
static int gather(rt_assembly *a, const rt_unit *t, const int64_t *sums, uint32_t n_units)
{
    struct rt_pending **at = &a->gather[t->y0];
    while (*at && !((*at)->unit.y1 == t->y1 && (*at)->unit.s0 == t->s0 && (*at)->unit.s1 == t->s1))
        at = &(*at)->next;
    if (!*at) {
        struct rt_pending *block = malloc(sizeof *block);
        /* not zeroed: the tiles cover every column once before it is used */
        int64_t *sums0 = malloc(unit_len(a, t) * sizeof *sums0);
        if (!block || !sums0) {
            free(block);
            free(sums0);
            return RT_ENOMEM;
        }
        *block = (struct rt_pending){{0, t->y0, t->y1, t->s0, t->s1, 0, a->sched.width}, sums0, 0, 0, NULL};
        *at = block;
        a->n_gather++;
    }
    struct rt_pending *g = *at;
    const size_t ch = a->row / a->sched.width, w = (size_t)(t->x1 - t->x0) * ch;
    for (uint32_t y = 0; y < t->y1 - t->y0; y++)
        memcpy(g->sums + y * a->row + t->x0 * ch, sums + y * w, w * sizeof *sums);
    g->n_units += n_units;
    g->cols += t->x1 - t->x0;
    if (g->cols < a->sched.width)
        return RT_OK;
    struct rt_pending full = *g;
    *at = g->next;
    free(g);
    a->n_gather--;
    if (!rt_sched_can_commit(&a->sched, &full.unit))
        return keep_owned(a, &full.unit, full.sums, full.n_units);
    commit(a, &full.unit, full.sums, full.n_units);
    free(full.sums);
    commit_pending(a);
    return RT_OK;
}

void rt_assembly_account(rt_assembly *a, int rank, const rt_unit *u, uint64_t segs, double start, double end)
{
    a->segments += segs;
    if (u->id < a->sched.n_units)
        a->unit_secs[u->id] = end - start;
    if (a->fst) {
        struct rt_frame_acct *fa = &a->fst[rt_sched_frame(&a->sched, u->y0)];
        fa->segments += segs;
        fa->units++;
    }
    if (rank >= 0 && rank < a->ranks)
        rt_rank_stats_add(&a->stats[rank], u, a->sched.width, a->sched.samples, segs, start, end);
    /* Out of memory for the trace: it misses events, the render goes on. */
    if (a->tracing && rt_array_reserve((void **)&a->trace, &a->cap_trace, a->n_trace + 1, sizeof *a->trace) == RT_OK)
        a->trace[a->n_trace++] = (rt_trace_event){.rank = rank, .unit = *u, .start = start, .end = end};
}

int rt_assembly_sums(rt_assembly *a, const rt_unit *block, const int64_t *sums, uint32_t n_units)
{
    if (!whole(a, block))
        return gather(a, block, sums, n_units);
    if (!rt_sched_can_commit(&a->sched, block))
        return keep(a, block, sums, n_units);
    commit(a, block, sums, n_units);
    commit_pending(a);
    return RT_OK;
}

int rt_assembly_add(rt_assembly *a, int rank, const rt_unit *u, const int64_t *sums, uint64_t segs, double start,
                    double end)
{
    rt_assembly_account(a, rank, u, segs, start, end);
    return rt_assembly_sums(a, u, sums, 1);
}
