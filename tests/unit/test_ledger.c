/* test_ledger.c - rank 0's book of units: each unit is handed out once,
 * reported and taken in only by its owner, a lost rank's units (assigned
 * or done) are handed out again before new ones and in schedule order,
 * its later words are refused, passes finish when their units are done,
 * and a rank continues the sample ranges of the band it started. */
#include <stdlib.h>

#include "check.h"
#include "ledger.h"
#include "status.h"

int main(void)
{
    rt_job job = {.width = 8,
                  .height = 20,
                  .samples = 12,
                  .max_depth = 8,
                  .seed = 1,
                  .diffuse = RT_DIFFUSE_LAMBERTIAN,
                  .sampler = RT_SAMPLER_SOBOL,
                  .roulette = 1};
    /* bands of 2 rows, 3 ranks, 3 passes; 8 columns: too narrow for tiles */
    rt_sched_params p = {.band = 2,
                         .max_band = 4,
                         .ranks = 3,
                         .units_per_rank = 8,
                         .min_samples = 1,
                         .passes = 3,
                         .split = RT_SPLIT_COLUMNS};
    rt_sched s;
    CHECK_EQ_INT(rt_sched_init(&s, &job, &p, NULL), RT_OK);
    rt_ledger L;
    CHECK_EQ_INT(rt_ledger_init(&L, &s, 3), RT_OK);
    const uint32_t n = s.n_units;
    CHECK(n >= 30);
    /* Passes: units of pass k render samples up to its end, and together
     * every unit. */
    uint32_t in_passes = 0;
    for (uint32_t k = 0; k < L.passes; k++)
        in_passes += L.pass_left[k];
    CHECK_EQ_INT(in_passes, n);
    int pass_ok = 1;
    for (uint32_t i = 0; i < n; i++)
        pass_ok &= s.units[i].s1 <= rt_sched_pass_end(&s, L.pass[i]) &&
                   (L.pass[i] == 0 || s.units[i].s0 >= rt_sched_pass_end(&s, L.pass[i] - 1));
    CHECK(pass_ok);

    /* Rank 1 takes 4, rank 2 takes 3; reports and sums only by the owner. */
    rt_unit a[4], b[3], u;
    for (int k = 0; k < 4; k++)
        CHECK(rt_ledger_take(&L, &s, 1, &a[k]));
    for (int k = 0; k < 3; k++)
        CHECK(rt_ledger_take(&L, &s, 2, &b[k]));
    CHECK_EQ_INT(L.assigned[1], 4);
    CHECK_EQ_INT(rt_ledger_done(&L, 2, a[0].id), 0); /* not rank 2's */
    CHECK_EQ_INT(rt_ledger_done(&L, 1, a[0].id), 1);
    CHECK_EQ_INT(rt_ledger_done(&L, 1, a[0].id), 0); /* twice */
    CHECK_EQ_INT(rt_ledger_in(&L, 1, a[1].id), 0);   /* not done yet */
    CHECK_EQ_INT(rt_ledger_done(&L, 1, a[1].id), 1);
    CHECK_EQ_INT(rt_ledger_in(&L, 1, a[1].id), 1);
    CHECK_EQ_INT(rt_ledger_done(&L, 1, 99999), 0);   /* no such unit */
    CHECK_EQ_INT(L.held[1], 1);                     /* a[0]: done, sums still on rank 1 */
    /* what losing rank 1 throws away: a[0]'s rendering only (a[1] is in,
     * a[2] and a[3] not done) */
    double *secs = calloc(n, sizeof *secs);
    for (uint32_t i = 0; i < n; i++)
        secs[i] = 1.0 + i;
    CHECK_NEAR(rt_ledger_held_sum(&L, 1, secs), 1.0 + a[0].id, 0);
    CHECK_NEAR(rt_ledger_held_sum(&L, 2, secs), 0, 0);
    free(secs);

    /* Rank 1 is lost: a[0] (done, not in), a[2], a[3] (assigned) come back;
     * a[1] is in the image and stays. */
    CHECK_EQ_INT(rt_ledger_lose(&L, 1), 3);
    CHECK_EQ_INT(L.assigned[1] + L.held[1], 0);
    CHECK_EQ_INT(rt_ledger_in(&L, 1, a[0].id), 0);   /* its late sums are refused */
    CHECK_EQ_INT(rt_ledger_done(&L, 1, a[2].id), 0); /* and its late reports */
    /* Handed out again first, in schedule order, to whoever asks. */
    CHECK(rt_ledger_take(&L, &s, 2, &u));
    CHECK_EQ_INT(u.id, a[0].id);
    CHECK(rt_ledger_take(&L, &s, 2, &u));
    CHECK_EQ_INT(u.id, a[2].id);
    CHECK(rt_ledger_take(&L, &s, 0, &u));
    CHECK_EQ_INT(u.id, a[3].id);
    /* Then new units by affinity. The rows of 20 are fewer than 3 ranks x
     * 8 units want: each band's pass is split into 2 sample ranges, a
     * group. Rank 1 took groups 0 and 1 whole, rank 2 group 2 and the first
     * range of group 3 (b[2]); rank 0 starts group 4, rank 2 continues
     * group 3. */
    CHECK_EQ_INT(L.glen[0], 2);
    CHECK_EQ_INT(a[1].id, a[0].id + 1);
    CHECK_EQ_INT(b[2].id, 6);
    CHECK(rt_ledger_take(&L, &s, 0, &u));
    CHECK_EQ_INT(u.id, b[2].id + 2);
    CHECK(rt_ledger_take(&L, &s, 2, &u));
    CHECK_EQ_INT(u.id, b[2].id + 1);
    CHECK_EQ_INT(u.s0, b[2].s1); /* its next sample range */

    /* Everything else done and in, by rank 2 and rank 0: each unit once. */
    rt_ledger_free(&L);
    rt_sched_free(&s);
    CHECK_EQ_INT(rt_sched_init(&s, &job, &p, NULL), RT_OK);
    CHECK_EQ_INT(rt_ledger_init(&L, &s, 3), RT_OK);
    uint32_t *seen = calloc(n, sizeof *seen), taken = 0;
    int rank = 0, passes_seen_in_order = 1;
    while (rt_ledger_take(&L, &s, rank, &u)) {
        seen[u.id]++;
        taken++;
        CHECK(rt_ledger_done(&L, rank, u.id));
        if (taken == n / 2)
            rt_ledger_lose(&L, rank); /* one more loss midway: its units come back */
        else
            CHECK(rt_ledger_in(&L, rank, u.id));
        for (uint32_t k = 0; k + 1 < L.passes; k++)
            passes_seen_in_order &= !rt_ledger_pass_done(&L, k + 1) || rt_ledger_pass_done(&L, k);
        rank = (rank + 1) % 3;
    }
    int once = 1, extra = 0;
    for (uint32_t i = 0; i < n; i++) {
        once &= seen[i] >= 1;
        extra += seen[i] - 1;
        CHECK_EQ_INT(L.state[i], RT_UNIT_IN);
    }
    CHECK(once);
    CHECK(extra >= 1); /* the lost units were handed out again */
    CHECK(passes_seen_in_order);
    for (uint32_t k = 0; k < L.passes; k++)
        CHECK(rt_ledger_pass_done(&L, k));
    free(seen);
    rt_ledger_free(&L);
    rt_sched_free(&s);
    /* A frame job's cap: once the units of the first two frames are out,
     * take says "not yet" (-1), not "none left" (0), until a frame is
     * complete and released; frame_done follows the reports. */
    {
        rt_job fj = job;
        fj.height = 4 * 5; /* 5 frames of 4 rows */
        rt_sched_params fp = {.band = 2, .max_band = 4, .ranks = 2, .units_per_rank = 8, .min_samples = 1,
                              .passes = 1, .split = RT_SPLIT_COLUMNS, .frame_rows = 4, .frames_cap = 2};
        rt_sched fs;
        rt_ledger FL;
        CHECK_EQ_INT(rt_sched_init(&fs, &fj, &fp, NULL), RT_OK);
        CHECK_EQ_INT(rt_ledger_init(&FL, &fs, 2), RT_OK);
        CHECK_EQ_INT(fs.n_units, 10);
        rt_unit got[4], v;
        for (int k = 0; k < 4; k++)
            CHECK_EQ_INT(rt_ledger_take(&FL, &fs, 1, &got[k]), 1);
        CHECK_EQ_INT(rt_ledger_take(&FL, &fs, 1, &v), -1);
        CHECK_EQ_INT(got[3].y1, 8); /* frames 0 and 1, no further */
        CHECK(!rt_ledger_frame_done(&FL, 0));
        for (int k = 0; k < 2; k++) {
            CHECK(rt_ledger_done(&FL, 1, got[k].id));
            CHECK(rt_ledger_in(&FL, 1, got[k].id));
            rt_sched_commit(&fs, &got[k]);
        }
        CHECK(rt_ledger_frame_done(&FL, 0));
        CHECK(!rt_ledger_frame_done(&FL, 1));
        CHECK_EQ_INT(rt_ledger_take(&FL, &fs, 0, &v), -1); /* complete, not released */
        rt_sched_release(&fs, 0);
        CHECK_EQ_INT(rt_ledger_take(&FL, &fs, 0, &v), 1);
        CHECK_EQ_INT(v.y0, 8); /* frame 2's */
        /* A lost rank's units of a frame in flight: one done (its sums
         * never sent) and one in hand. Both count again as frame 1's units
         * left, so the frame completes only when rank 0 has done both. */
        CHECK(rt_ledger_done(&FL, 1, got[2].id));
        CHECK(!rt_ledger_frame_done(&FL, 1));
        CHECK_EQ_INT(rt_ledger_lose(&FL, 1), 2);
        CHECK_EQ_INT(FL.frame_left[1], 2);
        for (int k = 0; k < 2; k++) {
            rt_unit w;
            CHECK_EQ_INT(rt_ledger_take(&FL, &fs, 0, &w), 1);
            CHECK_EQ_INT(w.id, got[2 + k].id); /* the requeued units, earliest first */
            CHECK(!rt_ledger_frame_done(&FL, 1));
            CHECK(rt_ledger_done(&FL, 0, w.id));
            CHECK(rt_ledger_in(&FL, 0, w.id));
        }
        CHECK(rt_ledger_frame_done(&FL, 1));
        CHECK_EQ_INT(FL.frame_left[1], 0);
        rt_ledger_free(&FL);
        rt_sched_free(&fs);
    }
    CHECK_DONE();
}
