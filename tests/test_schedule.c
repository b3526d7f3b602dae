/* test_schedule.c - work units cover every (row, sample) exactly once, for
 * any band setting, rank count and set of rows restored from a checkpoint;
 * guided sizes shrink towards the end; few rows split into sample ranges. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "schedule.h"
#include "status.h"

static int covers_once(rt_sched *s, uint32_t H, uint32_t S, const uint8_t *done, uint32_t *max_rows)
{
    uint32_t *hits = calloc((size_t)H * S, sizeof *hits);
    rt_unit u;
    int ok = 1;
    *max_rows = 0;
    while (rt_sched_next(s, &u)) {
        ok &= u.y0 < u.y1 && u.y1 <= H && u.s0 < u.s1 && u.s1 <= S;
        if (u.y1 - u.y0 > *max_rows)
            *max_rows = u.y1 - u.y0;
        for (uint32_t y = u.y0; y < u.y1 && ok; y++)
            for (uint32_t k = u.s0; k < u.s1; k++)
                hits[(size_t)y * S + k]++;
        rt_sched_complete(s, &u);
    }
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t k = 0; k < S; k++)
            ok &= hits[(size_t)y * S + k] == ((done && done[y]) ? 0u : 1u);
    ok &= s->rows_done == H;
    free(hits);
    return ok;
}

int main(void)
{
    const uint32_t H = 97, S = 10;
    uint32_t max_rows;
    uint32_t bands[] = {0, 1, 5, 16, 200};
    uint32_t ranks[] = {1, 2, 7, 64, 1000};
    for (size_t b = 0; b < sizeof bands / sizeof *bands; b++) {
        for (size_t r = 0; r < sizeof ranks / sizeof *ranks; r++) {
            rt_sched_params p = {H, S, bands[b], 16, ranks[r], 8, 1};
            rt_sched s;
            CHECK_EQ_INT(rt_sched_init(&s, &p, NULL), RT_OK);
            int ok = covers_once(&s, H, S, NULL, &max_rows);
            CHECK(ok);
            if (!ok)
                fprintf(stderr, "  band %u ranks %u\n", bands[b], ranks[r]);
            if (bands[b])
                CHECK(max_rows <= bands[b]);
            else
                CHECK(max_rows <= 16);
            rt_sched_free(&s);
        }
    }
    /* Restored rows are skipped, and the rest still covered once. */
    uint8_t done[97] = {0};
    for (uint32_t y = 0; y < H; y += 3)
        done[y] = 1;
    done[50] = done[51] = done[52] = 1;
    rt_sched_params p = {H, S, 4, 16, 3, 8, 1};
    rt_sched s;
    CHECK_EQ_INT(rt_sched_init(&s, &p, done), RT_OK);
    CHECK(covers_once(&s, H, S, done, &max_rows));
    rt_sched_free(&s);

    /* Guided: the first unit is the largest, the last ones are single rows. */
    rt_sched_params g = {800, 500, 0, 16, 2, 8, 1};
    CHECK_EQ_INT(rt_sched_init(&s, &g, NULL), RT_OK);
    CHECK_EQ_INT(s.units[0].y1 - s.units[0].y0, 16);
    CHECK_EQ_INT(s.units[s.n_units - 1].y1 - s.units[s.n_units - 1].y0, 1);
    int shrinking = 1;
    for (uint32_t i = 1; i < s.n_units; i++)
        shrinking &= s.units[i].y1 - s.units[i].y0 <= s.units[i - 1].y1 - s.units[i - 1].y0;
    CHECK(shrinking);
    CHECK(s.n_units >= 16);
    rt_sched_free(&s);

    /* More ranks than rows: samples are split so every rank gets work. */
    rt_sched_params many = {8, 500, 0, 16, 1024, 4, 1};
    CHECK_EQ_INT(rt_sched_init(&s, &many, NULL), RT_OK);
    CHECK(s.n_units >= 1024);
    CHECK(s.units[0].s1 - s.units[0].s0 < 500);
    CHECK(covers_once(&s, 8, 500, NULL, &max_rows));
    rt_sched_free(&s);

    /* Row completion needs every sample range of the row. */
    rt_sched_params two = {2, 4, 1, 16, 4, 2, 1};
    CHECK_EQ_INT(rt_sched_init(&s, &two, NULL), RT_OK);
    CHECK(s.n_units > 2);
    rt_unit u;
    CHECK(rt_sched_next(&s, &u));
    CHECK_EQ_INT(rt_sched_complete(&s, &u), u.s1 - u.s0 == 4 ? 1 : 0);
    /* A lost unit is handed out again. */
    rt_unit v, w;
    CHECK(rt_sched_next(&s, &v));
    CHECK_EQ_INT(rt_sched_requeue(&s, v.id), RT_OK);
    CHECK(rt_sched_next(&s, &w));
    CHECK_EQ_INT(w.id, v.id);
    rt_sched_free(&s);
    CHECK_EQ_INT(rt_sched_init(&s, &(rt_sched_params){0, 4, 1, 16, 1, 8, 1}, NULL), RT_EINVAL);
    CHECK_DONE();
}
