/* held.c - a worker's sums not yet sent (see held.h). */
#include "held.h"

#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "status.h"

void rt_held_init(rt_held *h, uint32_t width, size_t ch)
{
    memset(h, 0, sizeof *h);
    h->width = width;
    h->ch = ch;
}

void rt_held_free_pieces(rt_piece *p, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        free(p[i].sums);
        free(p[i].ids);
    }
    free(p);
}

void rt_held_free(rt_held *h)
{
    rt_held_free_pieces(h->pieces, h->n);
    memset(h, 0, sizeof *h);
}

static int overlaps(const rt_piece *p, const rt_unit *u)
{
    return p->y0 < u->y1 && u->y0 < p->y1 && p->x0 < u->x1 && u->x0 < p->x1;
}

/* The piece u extends: the same whole rows, samples up to u's first. */
static rt_piece *extended(const rt_held *h, const rt_unit *u)
{
    if (u->x0 != 0 || u->x1 != h->width)
        return NULL;
    for (size_t i = 0; i < h->n; i++) {
        rt_piece *p = &h->pieces[i];
        if (p->y0 == u->y0 && p->y1 == u->y1 && p->x0 == 0 && p->x1 == h->width && p->s1 == u->s0)
            return p;
    }
    return NULL;
}

int rt_held_fits(const rt_held *h, const rt_unit *u)
{
    if (extended(h, u))
        return 1;
    for (size_t i = 0; i < h->n; i++)
        if (overlaps(&h->pieces[i], u))
            return 0;
    return 1;
}

static int add_id(rt_piece *p, uint32_t id)
{
    if (rt_array_reserve((void **)&p->ids, &p->cap_ids, p->n_ids + 1, sizeof *p->ids))
        return RT_ENOMEM;
    p->ids[p->n_ids++] = id;
    return RT_OK;
}

int rt_held_add(rt_held *h, const rt_unit *u, const int64_t *sums)
{
    const size_t n = (size_t)rt_unit_pixels(u) * h->ch;
    rt_piece *p = extended(h, u);
    if (p) {
        if (add_id(p, u->id))
            return RT_ENOMEM;
        for (size_t i = 0; i < n; i++)
            p->sums[i] += sums[i];
        p->s1 = u->s1;
        return RT_OK;
    }
    if (!rt_held_fits(h, u))
        return RT_EINVAL;
    if (rt_array_reserve((void **)&h->pieces, &h->cap, h->n + 1, sizeof *h->pieces))
        return RT_ENOMEM;
    p = &h->pieces[h->n];
    *p = (rt_piece){.y0 = u->y0,
                    .y1 = u->y1,
                    .s0 = u->s0,
                    .s1 = u->s1,
                    .x0 = u->x0,
                    .x1 = u->x1,
                    .sums = malloc(n * sizeof *p->sums)};
    if (!p->sums || add_id(p, u->id)) {
        free(p->sums);
        return RT_ENOMEM;
    }
    memcpy(p->sums, sums, n * sizeof *sums);
    h->n++;
    h->bytes += n * sizeof *sums;
    return RT_OK;
}

rt_piece *rt_held_take(rt_held *h, size_t *n)
{
    rt_piece *p = h->pieces;
    *n = h->n;
    h->pieces = NULL;
    h->n = h->cap = 0;
    h->bytes = 0;
    return p;
}
