/* ledger.c - rank 0's book of units (see ledger.h). */
#include "ledger.h"

#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "status.h"

static int later_first(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? 1 : x > y ? -1 : 0;
}

int rt_ledger_init(rt_ledger *L, const rt_sched *s, int ranks)
{
    memset(L, 0, sizeof *L);
    L->n = s->n_units;
    L->ranks = ranks;
    L->passes = s->passes;
    size_t n = L->n ? L->n : 1, r = ranks > 0 ? (size_t)ranks : 1;
    L->state = calloc(n, sizeof *L->state);
    L->owner = calloc(n, sizeof *L->owner);
    L->pass = calloc(n, sizeof *L->pass);
    L->assigned = calloc(r, sizeof *L->assigned);
    L->held = calloc(r, sizeof *L->held);
    L->pass_left = calloc(L->passes ? L->passes : 1, sizeof *L->pass_left);
    L->frames = s->frames ? s->frames : 1;
    L->frame_left = calloc(L->frames, sizeof *L->frame_left);
    L->frame = calloc(n, sizeof *L->frame);
    if (!L->state || !L->owner || !L->pass || !L->assigned || !L->held || !L->pass_left || !L->frame_left ||
        !L->frame) {
        rt_ledger_free(L);
        return RT_ENOMEM;
    }
    L->gfirst = calloc(n, sizeof *L->gfirst);
    L->glen = calloc(n, sizeof *L->glen);
    L->gnext = calloc(n, sizeof *L->gnext);
    L->cur = malloc(r * sizeof *L->cur);
    if (!L->gfirst || !L->glen || !L->gnext || !L->cur) {
        rt_ledger_free(L);
        return RT_ENOMEM;
    }
    for (size_t k = 0; k < r; k++)
        L->cur[k] = -1;
    /* groups: runs of units with the same rows whose samples follow on */
    for (uint32_t i = 0; i < L->n; i++) {
        const rt_unit *u = &s->units[i], *prev = i ? &s->units[i - 1] : NULL;
        if (!prev || prev->y0 != u->y0 || prev->y1 != u->y1 || prev->x0 != u->x0 || prev->x1 != u->x1 ||
            prev->s1 != u->s0)
            L->gfirst[L->n_groups++] = i;
        L->glen[L->n_groups - 1]++;
    }
    /* A unit belongs to the pass whose samples it renders (units never
     * straddle a pass). */
    for (uint32_t i = 0, k = 0; i < L->n; i++) {
        const rt_unit *u = &s->units[i];
        k = 0;
        while (k + 1 < L->passes && u->s1 > rt_sched_pass_end(s, k))
            k++;
        L->pass[i] = k;
        L->pass_left[k]++;
        L->frame[i] = rt_sched_frame(s, u->y0);
        L->frame_left[L->frame[i]]++;
    }
    return RT_OK;
}

void rt_ledger_free(rt_ledger *L)
{
    free(L->state);
    free(L->owner);
    free(L->pass);
    free(L->requeue);
    free(L->assigned);
    free(L->held);
    free(L->pass_left);
    free(L->frame_left);
    free(L->frame);
    free(L->gfirst);
    free(L->glen);
    free(L->gnext);
    free(L->cur);
    memset(L, 0, sizeof *L);
}

/* The group rank's next new unit comes from: its own while ready, else
 * the first not begun, else any with units left; -1 when none is ready
 * (the cap), -2 when none is left. */
static int32_t next_group(rt_ledger *L, const rt_sched *s, int rank)
{
#define READY(g) rt_sched_ready(s, &s->units[L->gfirst[g] + L->gnext[g]])
    int32_t g = L->cur[rank];
    if (g >= 0 && L->gnext[g] < L->glen[g] && READY(g))
        return g;
    while (L->fresh < L->n_groups && L->gnext[L->fresh] > 0)
        L->fresh++;
    while (L->any < L->n_groups && L->gnext[L->any] == L->glen[L->any])
        L->any++;
    if (L->fresh < L->n_groups && READY(L->fresh))
        return (int32_t)L->fresh;
    if (L->any < L->n_groups && READY(L->any))
        return (int32_t)L->any;
#undef READY
    return L->fresh < L->n_groups || L->any < L->n_groups ? -1 : -2;
}

int rt_ledger_take(rt_ledger *L, rt_sched *s, int rank, rt_unit *u)
{
    if (L->n_requeue) {
        *u = s->units[L->requeue[--L->n_requeue]];
    } else {
        int32_t g = next_group(L, s, rank);
        if (g < 0)
            return g == -1 ? -1 : 0;
        *u = s->units[L->gfirst[g] + L->gnext[g]++];
        L->cur[rank] = g;
    }
    L->state[u->id] = RT_UNIT_ASSIGNED;
    L->owner[u->id] = rank;
    L->assigned[rank]++;
    return 1;
}

int rt_ledger_waiting(rt_ledger *L, const rt_sched *s, int rank)
{
    return !L->n_requeue && next_group(L, s, rank) == -1;
}

int rt_ledger_done(rt_ledger *L, int rank, uint32_t id)
{
    if (id >= L->n || L->state[id] != RT_UNIT_ASSIGNED || L->owner[id] != rank)
        return 0;
    L->state[id] = RT_UNIT_DONE;
    L->assigned[rank]--;
    L->held[rank]++;
    L->pass_left[L->pass[id]]--;
    L->frame_left[L->frame[id]]--;
    return 1;
}

int rt_ledger_in(rt_ledger *L, int rank, uint32_t id)
{
    if (id >= L->n || L->state[id] != RT_UNIT_DONE || L->owner[id] != rank)
        return 0;
    L->state[id] = RT_UNIT_IN;
    L->held[rank]--;
    return 1;
}

double rt_ledger_held_sum(const rt_ledger *L, int rank, const double *per_unit)
{
    double sum = 0;
    for (uint32_t i = 0; L->held[rank] && i < L->n; i++)
        if (L->owner[i] == rank && L->state[i] == RT_UNIT_DONE)
            sum += per_unit[i];
    return sum;
}

uint32_t rt_ledger_lose(rt_ledger *L, int rank)
{
    uint32_t back = 0;
    for (uint32_t i = 0; i < L->n; i++) {
        if (L->owner[i] != rank || (L->state[i] != RT_UNIT_ASSIGNED && L->state[i] != RT_UNIT_DONE))
            continue;
        if (L->state[i] == RT_UNIT_DONE) {
            L->pass_left[L->pass[i]]++;
            L->frame_left[L->frame[i]]++;
        }
        if (rt_array_reserve((void **)&L->requeue, &L->cap_requeue, L->n_requeue + 1, sizeof *L->requeue))
            return back; /* out of memory: the job cannot finish; the caller sees units left */
        L->state[i] = RT_UNIT_QUEUED;
        L->owner[i] = -1;
        L->requeue[L->n_requeue++] = i;
        back++;
    }
    /* Handed out again in schedule order: the stack's top is the earliest. */
    qsort(L->requeue, L->n_requeue, sizeof *L->requeue, later_first);
    L->assigned[rank] = L->held[rank] = 0;
    return back;
}

int rt_ledger_pass_done(const rt_ledger *L, uint32_t k) { return k < L->passes && L->pass_left[k] == 0; }

int rt_ledger_frame_done(const rt_ledger *L, uint32_t k) { return k < L->frames && L->frame_left[k] == 0; }
