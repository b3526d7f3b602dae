/* test_schedule.c - work units cover every (pixel, sample) exactly once,
 * for any band setting, rank count, number of passes, split and set of
 * samples restored from a checkpoint; committing in schedule order is always
 * possible; guided sizes shrink towards the end; few rows split into column
 * tiles, or sample ranges when too narrow or asked. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "schedule.h"
#include "status.h"

/* Hands out every unit, commits them in a scrambled arrival order (holding
 * early ones as the farm does) and checks coverage. */
static int covers_once(rt_sched *s, uint32_t H, uint32_t S, const uint32_t *start, uint32_t *max_rows)
{
    const uint32_t W = s->width;
    uint32_t *hits = calloc((size_t)H * W * S, sizeof *hits);
    rt_unit *got = malloc((s->n_units + 1) * sizeof *got);
    uint32_t n = 0;
    int ok = 1;
    *max_rows = 0;
    rt_unit u;
    while (rt_sched_next(s, &u)) {
        ok &= u.y0 < u.y1 && u.y1 <= H && u.x0 < u.x1 && u.x1 <= W && u.s0 < u.s1 && u.s1 <= S;
        if (u.y1 - u.y0 > *max_rows)
            *max_rows = u.y1 - u.y0;
        for (uint32_t y = u.y0; y < u.y1 && ok; y++)
            for (uint32_t x = u.x0; x < u.x1; x++)
                for (uint32_t k = u.s0; k < u.s1; k++)
                    hits[((size_t)y * W + x) * S + k]++;
        /* the farm gathers a row's tiles into one block (assemble.c): the
         * first tile stands for it, the others are in with it */
        if (u.x0 > 0)
            continue;
        u.x1 = W;
        got[n++] = u;
    }
    /* arrival order: reverse within groups of 5 */
    for (uint32_t g = 0; g < n; g += 5) {
        uint32_t e = g + 5 < n ? g + 5 : n;
        for (uint32_t a = g, b = e - 1; a < b; a++, b--) {
            rt_unit t = got[a];
            got[a] = got[b];
            got[b] = t;
        }
    }
    uint32_t left = n, rounds = 0;
    while (left && rounds++ < n + 5) {
        for (uint32_t i = 0; i < n; i++) {
            if (got[i].y1 && rt_sched_can_commit(s, &got[i])) {
                rt_sched_commit(s, &got[i]);
                got[i].y1 = 0;
                left--;
            }
        }
    }
    ok &= left == 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            for (uint32_t k = 0; k < S; k++)
                ok &= hits[((size_t)y * W + x) * S + k] == ((start && k < start[y]) ? 0u : 1u);
    ok &= s->rows_done == H && rt_sched_min_committed(s) == S;
    free(hits);
    free(got);
    return ok;
}

/* A job of h rows at s samples and the schedule's knobs for it. */
typedef struct plan {
    rt_job job;
    rt_sched_params p;
} plan;

static plan P(uint32_t h, uint32_t s, uint32_t band, uint32_t ranks, uint32_t per_rank, uint32_t passes)
{
    /* 8 columns: narrower than a tile (16), so few rows split samples */
    plan p = {.job = {.width = 8,
                      .height = h,
                      .samples = s,
                      .max_depth = 50,
                      .seed = 1,
                      .diffuse = RT_DIFFUSE_LAMBERTIAN,
                      .sampler = RT_SAMPLER_SOBOL,
                      .roulette = 1},
              .p = {.band = band,
                    .max_band = 16,
                    .ranks = ranks,
                    .units_per_rank = per_rank,
                    .min_samples = 1,
                    .passes = passes,
                    .split = RT_SPLIT_COLUMNS}};
    return p;
}

/* A frame job (issue 37): 6 frames of 13 rows as one schedule of 78 rows.
 * Units never cross a frame, for any band, rank count or split, and cover
 * every sample once; guided sizes shrink towards the end of the range, not
 * of each frame; the cap: a unit of frame k is ready only while every
 * frame before k - 2 + 1 is released, and releasing a complete frame
 * readies the next one. */
static void frames_cases(void)
{
    const uint32_t H = 13, F = 6, S = 6;
    uint32_t bands[] = {0, 1, 5, 16}, ranks[] = {1, 3, 64, 1000}, max_rows;
    for (size_t b = 0; b < sizeof bands / sizeof *bands; b++)
        for (size_t r = 0; r < sizeof ranks / sizeof *ranks; r++)
            for (int split = RT_SPLIT_COLUMNS; split <= RT_SPLIT_SAMPLES; split++) {
                plan p = P(H * F, S, bands[b], ranks[r], 8, 1);
                p.job.width = 64;
                p.p.min_cols = 4;
                p.p.split = split;
                p.p.frame_rows = H;
                rt_sched s;
                CHECK_EQ_INT(rt_sched_init(&s, &p.job, &p.p, NULL), RT_OK);
                uint32_t crossing = 0;
                for (uint32_t i = 0; i < s.n_units; i++)
                    crossing += s.units[i].y0 / H != (s.units[i].y1 - 1) / H;
                CHECK_EQ_INT(crossing, 0);
                CHECK_EQ_INT(s.frames, F);
                CHECK(covers_once(&s, H * F, S, NULL, &max_rows));
                for (uint32_t k = 0; k < F; k++)
                    CHECK(rt_sched_frame_complete(&s, k));
                rt_sched_free(&s);
            }
    /* guided over the whole range (6 frames of 100 rows): frame 0 starts
     * with full bands, single rows come only in the last frame (but a
     * frame's last row cut off by the frame's end) */
    plan g = P(100 * F, S, 0, 2, 8, 1);
    g.p.frame_rows = 100;
    rt_sched s;
    CHECK_EQ_INT(rt_sched_init(&s, &g.job, &g.p, NULL), RT_OK);
    CHECK_EQ_INT(s.units[0].y1 - s.units[0].y0, 16);
    uint32_t single_early = 0, single = 0;
    for (uint32_t i = 0; i < s.n_units; i++) {
        single += s.units[i].y1 - s.units[i].y0 == 1;
        single_early += s.units[i].y1 - s.units[i].y0 == 1 && s.units[i].y0 / 100 < F - 1 &&
                        s.units[i].y1 % 100 != 0; /* a frame's last row, cut off, aside */
    }
    CHECK_EQ_INT(single_early, 0);
    CHECK(single > 0);
    rt_sched_free(&s);
    /* the cap */
    plan c = P(H * F, S, 5, 1, 8, 1);
    c.p.frame_rows = H;
    c.p.frames_cap = 2;
    CHECK_EQ_INT(rt_sched_init(&s, &c.job, &c.p, NULL), RT_OK);
    uint32_t ready[6] = {0}, blocked[6] = {0};
    for (uint32_t i = 0; i < s.n_units; i++)
        (rt_sched_ready(&s, &s.units[i]) ? ready : blocked)[s.units[i].y0 / H]++;
    CHECK_EQ_INT(blocked[0] + blocked[1], 0);
    CHECK_EQ_INT(ready[2] + ready[3] + ready[4] + ready[5], 0);
    rt_unit u;
    while (rt_sched_next(&s, &u) && u.y0 < 2 * H) /* frames 0 and 1, all of them */
        rt_sched_commit(&s, &u);
    CHECK(rt_sched_frame_complete(&s, 1));
    rt_sched_release(&s, 1); /* complete but frame 0 is not released: no move */
    CHECK(!rt_sched_ready(&s, &u));
    CHECK_EQ_INT(s.low, 0);
    rt_sched_release(&s, 0);
    CHECK_EQ_INT(s.low, 2);
    CHECK(rt_sched_ready(&s, &u)); /* frame 2's */
    const rt_unit f4 = {.y0 = 4 * H, .y1 = 4 * H + 1};
    CHECK(!rt_sched_ready(&s, &f4));
    rt_sched_release(&s, 2); /* not complete: ignored */
    CHECK_EQ_INT(s.low, 2);
    rt_sched_free(&s);
}

int main(void)
{
    const uint32_t H = 97, S = 10;
    uint32_t max_rows;
    uint32_t bands[] = {0, 1, 5, 16, 200};
    uint32_t ranks[] = {1, 2, 7, 64, 1000};
    uint32_t passes[] = {1, 3, 10};
    for (size_t b = 0; b < sizeof bands / sizeof *bands; b++)
        for (size_t r = 0; r < sizeof ranks / sizeof *ranks; r++)
            for (size_t q = 0; q < sizeof passes / sizeof *passes; q++) {
                plan p = P(H, S, bands[b], ranks[r], 8, passes[q]);
                rt_sched s;
                CHECK_EQ_INT(rt_sched_init(&s, &p.job, &p.p, NULL), RT_OK);
                int ok = covers_once(&s, H, S, NULL, &max_rows);
                CHECK(ok);
                if (!ok)
                    fprintf(stderr, "  band %u ranks %u passes %u\n", bands[b], ranks[r], passes[q]);
                CHECK(max_rows <= (bands[b] ? bands[b] : 16));
                rt_sched_free(&s);
            }
    /* Restored samples (whole and partial rows) are not planned again. */
    uint32_t start[97];
    for (uint32_t y = 0; y < H; y++)
        start[y] = y % 3 == 0 ? S : y % 3 == 1 ? 4 : 0;
    start[50] = start[51] = start[52] = 7;
    for (size_t q = 0; q < sizeof passes / sizeof *passes; q++) {
        plan p = P(H, S, 4, 3, 8, passes[q]);
        rt_sched s;
        CHECK_EQ_INT(rt_sched_init(&s, &p.job, &p.p, start), RT_OK);
        CHECK(covers_once(&s, H, S, start, &max_rows));
        rt_sched_free(&s);
    }
    /* Progressive: the units of pass k all come before those of pass k+1. */
    rt_sched s;
    plan pp = P(20, 12, 5, 2, 8, 3);
    CHECK_EQ_INT(rt_sched_init(&s, &pp.job, &pp.p, NULL), RT_OK);
    int ordered = 1;
    for (uint32_t i = 1; i < s.n_units; i++)
        ordered &= s.units[i].s0 >= s.units[i - 1].s0 || s.units[i].s1 <= s.units[i - 1].s1;
    CHECK(ordered);
    CHECK_EQ_INT(rt_sched_pass_end(&s, 0), 4);
    CHECK_EQ_INT(s.units[0].s1, 4);
    CHECK_EQ_INT(s.units[s.n_units - 1].s1, 12);
    rt_sched_free(&s);

    /* Guided: the first unit is the largest, the last ones are single rows. */
    plan g = P(800, 500, 0, 2, 8, 1);
    CHECK_EQ_INT(rt_sched_init(&s, &g.job, &g.p, NULL), RT_OK);
    CHECK_EQ_INT(s.units[0].y1 - s.units[0].y0, 16);
    CHECK_EQ_INT(s.units[s.n_units - 1].y1 - s.units[s.n_units - 1].y0, 1);
    int shrinking = 1;
    for (uint32_t i = 1; i < s.n_units; i++)
        shrinking &= s.units[i].y1 - s.units[i].y0 <= s.units[i - 1].y1 - s.units[i - 1].y0;
    CHECK(shrinking);
    CHECK(s.n_units >= 16);
    rt_sched_free(&s);

    /* More ranks than rows: samples are split so every rank gets work. */
    plan many = P(8, 500, 0, 1024, 4, 1);
    CHECK_EQ_INT(rt_sched_init(&s, &many.job, &many.p, NULL), RT_OK);
    CHECK(s.n_units >= 1024);
    CHECK(s.units[0].s1 - s.units[0].s0 < 500);
    CHECK(covers_once(&s, 8, 500, NULL, &max_rows));
    rt_sched_free(&s);

    /* Wide enough: few rows are cut into column tiles of whole sample
     * ranges, at least min_cols wide; the same with RT_SPLIT_SAMPLES gives
     * sample ranges; too many tiles wanted for the width gives sample
     * ranges too. */
    uint32_t tiles_seen = 0;
    for (size_t r = 0; r < sizeof ranks / sizeof *ranks; r++)
        for (size_t q = 0; q < sizeof passes / sizeof *passes; q++)
            for (int split = RT_SPLIT_COLUMNS; split <= RT_SPLIT_SAMPLES; split++) {
                plan p = P(H, S, 0, ranks[r], 8, passes[q]);
                p.job.width = 64;
                p.p.min_cols = 4;
                p.p.split = split;
                CHECK_EQ_INT(rt_sched_init(&s, &p.job, &p.p, NULL), RT_OK);
                int ok = covers_once(&s, H, S, NULL, &max_rows), tiles = 0, ranges = 0, narrow = 0;
                for (uint32_t i = 0; i < s.n_units; i++) {
                    tiles += s.units[i].x1 - s.units[i].x0 < 64;
                    ranges += s.units[i].s1 - s.units[i].s0 < S / s.passes;
                    narrow += s.units[i].x1 - s.units[i].x0 < 4;
                }
                const uint64_t k = ((uint64_t)ranks[r] * 8 + H - 1) / H;
                CHECK(ok);
                CHECK_EQ_INT(narrow, 0);
                CHECK_EQ_INT(tiles > 0, split == RT_SPLIT_COLUMNS && k > 1 && k <= 16);
                CHECK_EQ_INT(tiles > 0 && ranges > 0, 0);
                CHECK_EQ_INT(ranges > 0, k > 1 && (split == RT_SPLIT_SAMPLES || k > 16) && S / s.passes > 1);
                tiles_seen += tiles;
                rt_sched_free(&s);
            }
    CHECK(tiles_seen > 0);

    /* A unit cannot be committed before its predecessor in the row. */
    plan two = P(2, 4, 2, 4, 2, 1);
    CHECK_EQ_INT(rt_sched_init(&s, &two.job, &two.p, NULL), RT_OK);
    CHECK(s.n_units >= 2);
    rt_unit u0, u1;
    CHECK(rt_sched_next(&s, &u0));
    CHECK(rt_sched_next(&s, &u1));
    CHECK_EQ_INT(u1.s0, u0.s1);
    CHECK(!rt_sched_can_commit(&s, &u1));
    CHECK(rt_sched_can_commit(&s, &u0));
    rt_sched_free(&s);
    plan none = P(0, 4, 1, 1, 8, 1);
    CHECK_EQ_INT(rt_sched_init(&s, &none.job, &none.p, NULL), RT_EINVAL);

    frames_cases();
    CHECK_DONE();
}
