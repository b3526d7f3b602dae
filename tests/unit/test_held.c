/* test_held.c - a worker's held sums: a band's sample ranges (and its next
 * pass) become one piece, covering one contiguous range; a unit that would
 * give a row two ranges does not fit; column tiles of one row are pieces of
 * their own and never extended; the sums add up exactly; memory is
 * counted. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "held.h"
#include "status.h"

enum { W = 4 };

static void fill(const rt_unit *u, int64_t *sums)
{
    size_t n = (size_t)rt_unit_pixels(u) * 3;
    for (size_t i = 0; i < n; i++)
        sums[i] = (int64_t)(u->id * 1000 + i);
}

int main(void)
{
    rt_held h;
    rt_held_init(&h, W, 3);
    int64_t s1[2 * W * 3], s2[2 * W * 3], s3[W * 3];
    rt_unit a = {.id = 7, .y0 = 10, .y1 = 12, .s1 = 4, .x1 = W};
    rt_unit b = {.id = 8, .y0 = 10, .y1 = 12, .s0 = 4, .s1 = 9, .x1 = W};
    rt_unit c = {.id = 9, .y0 = 12, .y1 = 13, .s1 = 4, .x1 = W};
    rt_unit gap = {.id = 10, .y0 = 10, .y1 = 12, .s0 = 12, .s1 = 16, .x1 = W};
    rt_unit part = {.id = 11, .y0 = 11, .y1 = 13, .s0 = 9, .s1 = 12, .x1 = W};
    fill(&a, s1);
    fill(&b, s2);
    fill(&c, s3);
    CHECK_EQ_INT(rt_held_add(&h, &a, s1), RT_OK);
    CHECK_EQ_INT(rt_held_add(&h, &b, s2), RT_OK); /* extends a: samples 0-9 */
    CHECK_EQ_INT(rt_held_add(&h, &c, s3), RT_OK); /* other rows: a piece of its own */
    CHECK_EQ_INT(h.n, 2);
    CHECK_EQ_INT(h.bytes, (2 + 1) * W * 3 * sizeof(int64_t));
    CHECK_EQ_INT(rt_held_fits(&h, &gap), 0);  /* rows 10-11 would cover 0-9 and 12-16 */
    CHECK_EQ_INT(rt_held_fits(&h, &part), 0); /* overlaps both pieces, extends neither */
    CHECK_EQ_INT(rt_held_add(&h, &gap, s1), RT_EINVAL);
    size_t n;
    rt_piece *p = rt_held_take(&h, &n);
    CHECK_EQ_INT(n, 2);
    CHECK_EQ_INT(h.n + h.bytes, 0);
    CHECK_EQ_INT(p[0].y0, 10);
    CHECK_EQ_INT(p[0].s0, 0);
    CHECK_EQ_INT(p[0].s1, 9);
    CHECK_EQ_INT(p[0].n_ids, 2);
    CHECK_EQ_INT(p[0].ids[0], 7);
    CHECK_EQ_INT(p[0].ids[1], 8);
    int sums_ok = 1;
    for (size_t i = 0; i < 2 * W * 3; i++)
        sums_ok &= p[0].sums[i] == s1[i] + s2[i];
    CHECK(sums_ok);
    CHECK(memcmp(p[1].sums, s3, sizeof s3) == 0);
    rt_held_free_pieces(p, n);
    /* After the take, the gap unit fits: a new flush, a new piece. */
    CHECK_EQ_INT(rt_held_fits(&h, &gap), 1);
    CHECK_EQ_INT(rt_held_add(&h, &gap, s1), RT_OK);
    rt_held_free(&h);

    /* Column tiles: the two tiles of row 3 are two pieces (no overlap);
     * the next range of the left tile does not extend it (rank 0 gathers
     * tiles by the schedule's ranges) and so does not fit; a whole-row
     * unit of row 3 overlaps both. */
    rt_held_init(&h, W, 3);
    rt_unit l = {.id = 20, .y0 = 3, .y1 = 4, .s1 = 4, .x1 = 1};
    rt_unit r = {.id = 21, .y0 = 3, .y1 = 4, .s1 = 4, .x0 = 1, .x1 = W};
    rt_unit l2 = {.id = 22, .y0 = 3, .y1 = 4, .s0 = 4, .s1 = 8, .x1 = 1};
    rt_unit row = {.id = 23, .y0 = 3, .y1 = 4, .s0 = 4, .s1 = 8, .x1 = W};
    fill(&l, s1);
    fill(&r, s2);
    CHECK_EQ_INT(rt_held_add(&h, &l, s1), RT_OK);
    CHECK_EQ_INT(rt_held_fits(&h, &r), 1);
    CHECK_EQ_INT(rt_held_add(&h, &r, s2), RT_OK);
    CHECK_EQ_INT(h.n, 2);
    CHECK_EQ_INT(h.bytes, W * 3 * sizeof(int64_t));
    CHECK_EQ_INT(rt_held_fits(&h, &l2), 0);
    CHECK_EQ_INT(rt_held_fits(&h, &row), 0);
    p = rt_held_take(&h, &n);
    CHECK_EQ_INT(n, 2);
    CHECK_EQ_INT(p[1].x0, 1);
    CHECK_EQ_INT(p[1].x1, W);
    CHECK(memcmp(p[1].sums, s2, (W - 1) * 3 * sizeof *s2) == 0);
    rt_held_free_pieces(p, n);
    rt_held_free(&h);
    CHECK_DONE();
}
