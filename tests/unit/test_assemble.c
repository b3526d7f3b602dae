/* test_assemble.c - rank 0's result assembly without MPI: units arriving
 * in any order (as results from many ranks do) give the sums of one
 * in-order pass, bit for bit; a row's sum always covers samples [0,
 * committed) (what previews and checkpoints need); early arrivals wait and
 * are all drained; passes are noticed; each rank's account adds up. */
#include <stdlib.h>
#include <string.h>

#include "assemble.h"
#include "check.h"
#include "mem.h"
#include "rng.h"
#include "status.h"

enum { W = 5, H = 23, S = 12 };
static const rt_job JOB = {.width = W,
                           .height = H,
                           .samples = S,
                           .max_depth = 8,
                           .seed = 1,
                           .diffuse = RT_DIFFUSE_LAMBERTIAN,
                           .sampler = RT_SAMPLER_SOBOL,
                           .roulette = 1};
/* One pass for 8 ranks in column tiles at least 1 column wide: 3 tiles a
 * row of 5. */
static const rt_sched_params TILES = {.max_band = 4,
                                      .ranks = 8,
                                      .units_per_rank = 8,
                                      .min_samples = 1,
                                      .passes = 1,
                                      .min_cols = 1,
                                      .split = RT_SPLIT_COLUMNS};

/* The sums a unit of (rows, samples) would bring: each sample of each
 * channel a value of its own, so a unit added twice, missed, or added at
 * the wrong rows changes the total. */
static int64_t sample_value(uint32_t y, uint32_t x, uint32_t c, uint32_t s)
{
    return (int64_t)(((y * 31u + x) * 7u + c) * 1009u + s * 13u + 1u);
}

static void unit_sums(const rt_unit *u, int64_t *out)
{
    size_t i = 0;
    for (uint32_t y = u->y0; y < u->y1; y++)
        for (uint32_t x = u->x0; x < u->x1; x++)
            for (uint32_t c = 0; c < 3; c++, i++) {
                out[i] = 0;
                for (uint32_t s = u->s0; s < u->s1; s++)
                    out[i] += sample_value(y, x, c, s);
            }
}

/* Every row's sum covers exactly samples [0, committed[y]). */
static int rows_consistent(const rt_assembly *a)
{
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            for (uint32_t c = 0; c < 3; c++) {
                int64_t want = 0;
                for (uint32_t s = 0; s < a->sched.committed[y]; s++)
                    want += sample_value(y, x, c, s);
                if (a->acc[((size_t)y * W + x) * 3 + c] != want)
                    return 0;
            }
    return 1;
}

/* Plans a job of `passes` passes for `ranks` ranks (column tiles at least
 * min_cols wide), hands every unit out, then returns them in an order drawn
 * from seed (0: in order) from rank (k % ranks); checks consistency after
 * each. */
static void run(uint32_t passes, uint32_t ranks, uint64_t seed, uint32_t band, uint32_t min_cols)
{
    rt_sched_params p = {.band = band,
                         .max_band = 4,
                         .ranks = ranks,
                         .units_per_rank = 8,
                         .min_samples = 1,
                         .passes = passes,
                         .min_cols = min_cols,
                         .split = RT_SPLIT_COLUMNS};
    int64_t *acc = calloc((size_t)W * H * 3, sizeof *acc);
    rt_assembly a;
    CHECK_EQ_INT(rt_assembly_init(&a, &JOB, &p, NULL, acc, (int)ranks, 1), RT_OK);
    uint32_t n = a.sched.n_units;
    rt_unit *units = malloc(n * sizeof *units);
    for (uint32_t k = 0; k < n; k++)
        CHECK(rt_sched_next(&a.sched, &units[k]));
    rt_rng rng = rt_rng_for_stream(seed, 1);
    for (uint32_t k = n; seed && k > 1; k--) { /* Fisher-Yates */
        uint32_t j = (uint32_t)(rt_rng_double(&rng) * k);
        rt_unit t = units[k - 1];
        units[k - 1] = units[j];
        units[j] = t;
    }
    int64_t *sums = malloc((size_t)W * H * 3 * sizeof *sums);
    int consistent = 1, passes_seen = 0;
    for (uint32_t k = 0; k < n; k++) {
        unit_sums(&units[k], sums);
        CHECK_EQ_INT(rt_assembly_add(&a, (int)(k % ranks), &units[k], sums, 10, k, k + 0.5), RT_OK);
        consistent &= rows_consistent(&a);
        if (a.pass_ready) {
            passes_seen++;
            a.pass_ready = 0;
        }
    }
    CHECK(consistent);
    CHECK(rt_assembly_complete(&a));
    CHECK_EQ_INT(a.n_pending, 0);
    CHECK_EQ_INT(a.n_gather, 0);
    CHECK_EQ_INT(a.sched.rows_done, H);
    CHECK_EQ_INT(a.passes_done, passes > 1 ? passes : 0);
    CHECK_EQ_INT(passes_seen > 0, passes > 1);
    CHECK_EQ_U64(a.segments, (uint64_t)n * 10);
    double rows = 0, units_counted = 0, busy = 0;
    for (uint32_t r = 0; r < ranks; r++) {
        rows += a.stats[r].rows;
        units_counted += a.stats[r].units;
        busy += a.stats[r].busy;
    }
    CHECK_NEAR(rows, H, 1e-9);
    CHECK_NEAR(units_counted, n, 0);
    CHECK_NEAR(busy, 0.5 * n, 1e-9);
    CHECK_EQ_INT(a.n_trace, n);
    free(sums);
    free(units);
    rt_assembly_free(&a);
    free(acc);
}

/* A frame job: 3 frames of H rows as one schedule; each unit's sums go to
 * its frame's buffer (opened when a unit of it is handed out), whatever the
 * arrival order, and each frame comes out once complete, with its own
 * sums, units, segments and trace events. */
static void frames_case(void)
{
    rt_job job = JOB;
    job.height = 3 * H;
    const rt_sched_params p = {.max_band = 4, .ranks = 2, .units_per_rank = 8, .min_samples = 1, .passes = 1,
                               .split = RT_SPLIT_COLUMNS, .frame_rows = H, .frames_cap = 3};
    rt_assembly a;
    CHECK_EQ_INT(rt_assembly_init(&a, &job, &p, NULL, NULL, 2, 1), RT_OK);
    CHECK_EQ_INT(rt_assembly_frames(&a, NULL), RT_OK);
    const uint32_t n = a.sched.n_units;
    rt_unit *units = malloc(n * sizeof *units);
    uint32_t per_frame[3] = {0, 0, 0};
    for (uint32_t k = 0; k < n; k++) {
        CHECK(rt_sched_next(&a.sched, &units[k]));
        CHECK_EQ_INT(rt_assembly_open(&a, &units[k], k), RT_OK);
        per_frame[units[k].y0 / H]++;
    }
    CHECK_EQ_INT(a.in_flight, 3);
    rt_rng rng = rt_rng_for_stream(29, 1);
    for (uint32_t k = n; k > 1; k--) { /* Fisher-Yates */
        uint32_t j = (uint32_t)(rt_rng_double(&rng) * k);
        rt_unit t = units[k - 1];
        units[k - 1] = units[j];
        units[j] = t;
    }
    int64_t sums[W * H * 3];
    for (uint32_t k = 0; k < n; k++) {
        unit_sums(&units[k], sums);
        CHECK_EQ_INT(rt_assembly_add(&a, (int)(k % 2), &units[k], sums, 10, k, k + 0.5), RT_OK);
    }
    CHECK_EQ_INT(a.n_ready, 3);
    int seen[3] = {0, 0, 0}, right = 1;
    rt_farm_frame f;
    while (rt_assembly_next_frame(&a, &f, 99.0)) {
        CHECK(f.index < 3);
        seen[f.index]++;
        CHECK_EQ_INT(f.units, per_frame[f.index]);
        CHECK_EQ_U64(f.segments, 10u * per_frame[f.index]);
        CHECK_EQ_INT(f.n_trace, per_frame[f.index]);
        CHECK_EQ_INT(f.acc_bytes, (size_t)W * H * 3 * sizeof(int64_t));
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++)
                for (uint32_t c = 0; c < 3; c++) {
                    int64_t want = 0;
                    for (uint32_t s = 0; s < S; s++)
                        want += sample_value(f.index * H + y, x, c, s);
                    right &= f.acc[((size_t)y * W + x) * 3 + c] == want;
                }
        rt_mem_free(f.acc, f.acc_bytes);
        free(f.trace);
    }
    CHECK(right);
    CHECK(seen[0] == 1 && seen[1] == 1 && seen[2] == 1);
    CHECK_EQ_INT(a.in_flight, 0);
    CHECK_EQ_INT(a.in_flight_peak, 3);
    free(units);
    rt_assembly_free(&a);
}

int main(void)
{
    run(1, 1, 0, 0, 0);   /* in order */
    run(1, 4, 7, 0, 0);   /* shuffled bands */
    run(1, 64, 11, 0, 0); /* more ranks than rows, too narrow for tiles: sample ranges, shuffled */
    run(3, 5, 13, 2, 0);  /* progressive passes, shuffled */
    run(4, 64, 17, 1, 0); /* passes and sample ranges */
    run(1, 8, 19, 0, 1);  /* column tiles (3 a row), shuffled */
    run(3, 8, 23, 0, 1);  /* passes of column tiles, shuffled */
    {
        /* the tiles' widths: 1, 2 and 2 columns of 5 */
        const rt_sched_params p = TILES;
        rt_sched sc;
        CHECK_EQ_INT(rt_sched_init(&sc, &JOB, &p, NULL), RT_OK);
        CHECK_EQ_INT(sc.n_units, 3 * H);
        CHECK_EQ_INT(sc.units[0].x1 - sc.units[0].x0, 1);
        CHECK_EQ_INT(sc.units[2].x0, 3);
        CHECK_EQ_INT(sc.units[2].x1, W);
        CHECK_EQ_INT(sc.units[2].s0 + sc.units[2].s1, S);
        rt_sched_free(&sc);
    }

    /* A unit out of commit order is kept, not lost: with nothing else in,
     * the second sample range of a row waits for the first. */
    rt_sched_params p = {
        .max_band = 4, .ranks = 64, .units_per_rank = 8, .min_samples = 1, .passes = 1, .split = RT_SPLIT_COLUMNS};
    int64_t *acc = calloc((size_t)W * H * 3, sizeof *acc);
    rt_assembly a;
    CHECK_EQ_INT(rt_assembly_init(&a, &JOB, &p, NULL, acc, 1, 0), RT_OK);
    rt_unit first, later = {0, 0, 0, 0, 0, 0, 0};
    CHECK(rt_sched_next(&a.sched, &first));
    for (rt_unit u; rt_sched_next(&a.sched, &u);)
        if (u.y0 == first.y0 && u.s0 == first.s1) {
            later = u;
            break;
        }
    CHECK(later.s1 > later.s0);
    int64_t sums[W * H * 3];
    unit_sums(&later, sums);
    CHECK_EQ_INT(rt_assembly_add(&a, 0, &later, sums, 0, 0, 0), RT_OK);
    CHECK_EQ_INT(a.n_pending, 1);
    CHECK_EQ_INT(a.sched.committed[first.y0], 0);
    unit_sums(&first, sums);
    CHECK_EQ_INT(rt_assembly_add(&a, 0, &first, sums, 0, 0, 0), RT_OK);
    CHECK_EQ_INT(a.n_pending, 0);
    CHECK_EQ_INT(a.sched.committed[first.y0], later.s1);
    CHECK(rows_consistent(&a));
    rt_assembly_free(&a);

    /* A tile waits for the other tiles of its rows and samples, out of the
     * image: only the last brings the row in, whole. */
    memset(acc, 0, (size_t)W * H * 3 * sizeof *acc);
    const rt_sched_params pt = TILES;
    CHECK_EQ_INT(rt_assembly_init(&a, &JOB, &pt, NULL, acc, 1, 0), RT_OK);
    rt_unit t[3];
    for (int k = 0; k < 3; k++)
        CHECK(rt_sched_next(&a.sched, &t[k]));
    CHECK_EQ_INT(t[2].y0, t[0].y0);
    const int order[3] = {2, 0, 1};
    for (int k = 0; k < 3; k++) {
        unit_sums(&t[order[k]], sums);
        CHECK_EQ_INT(rt_assembly_add(&a, 0, &t[order[k]], sums, 0, 0, 0), RT_OK);
        CHECK_EQ_INT(a.sched.committed[t[0].y0], k < 2 ? 0 : S);
        CHECK_EQ_INT(a.n_gather, k < 2 ? 1 : 0);
        CHECK_EQ_INT(a.units_in, k < 2 ? 0 : 3);
        CHECK(rows_consistent(&a));
    }
    rt_assembly_free(&a);
    free(acc);
    frames_case();
    CHECK_DONE();
}
