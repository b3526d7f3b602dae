/* held.h - a worker's sums that rank 0 does not have yet. A finished unit's
 * sums extend the piece that holds the same whole rows up to the unit's
 * first sample (a band's sample ranges, or its next pass, rendered by the
 * same rank become one piece), or start a new one. So each row is sent to
 * rank 0 once per flush however many units of it the rank rendered, and a
 * piece always covers one contiguous sample range [s0, s1) of its rows:
 * rank 0 adds it in commit order like a unit (schedule.h). A column tile
 * is a piece of its own and is never extended: rank 0 gathers the tiles of
 * one range of rows and samples, so they must keep the schedule's ranges.
 * No MPI, no threads (the worker locks); tests/unit/test_held.c drives it. */
#ifndef RT_HELD_H
#define RT_HELD_H

#include <stddef.h>
#include <stdint.h>

#include "schedule.h"

typedef struct rt_piece {
    uint32_t y0, y1, s0, s1; /* rows, samples */
    uint32_t x0, x1;         /* columns */
    int64_t *sums;           /* (y1 - y0) * (x1 - x0) * ch */
    uint32_t *ids;           /* the units it holds */
    size_t n_ids, cap_ids;
} rt_piece;

typedef struct rt_held {
    uint32_t width; /* of the image */
    size_t ch;      /* values per pixel: the layout's ch (job.h) */
    rt_piece *pieces;
    size_t n, cap;
    size_t bytes; /* of sums held now */
} rt_held;

void rt_held_init(rt_held *h, uint32_t width, size_t ch);
void rt_held_free(rt_held *h);

/* Whether u's sums can be added without breaking "one contiguous range
 * per pixel": 0 when u shares pixels with a held piece it does not extend
 * (the caller flushes first). */
int rt_held_fits(const rt_held *h, const rt_unit *u);

/* Adds u's sums (laid out as rt_render_source's done gets them). RT_EINVAL
 * when it does not fit (rt_held_fits), RT_ENOMEM. */
int rt_held_add(rt_held *h, const rt_unit *u, const int64_t *sums);

/* Hands the pieces to the caller (who frees them with rt_held_free_pieces)
 * and starts empty. */
rt_piece *rt_held_take(rt_held *h, size_t *n);
void rt_held_free_pieces(rt_piece *p, size_t n);

#endif
