/* test_render.c - the determinism contract at the core: any split of the
 * work (bands, sample ranges, thread counts) sums to identical bits. */
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>

#include "core_internal.h"
#include "accel.h"
#include "check.h"
#include "image.h"
#include "render.h"
#include "status.h"

/* A source for rt_render_stream: hands out units[0..n) in order and adds
 * each finished unit into acc; with stop_at, sets *stop when asked for unit
 * stop_at (a signal arriving mid-job). */
typedef struct source {
    const rt_unit *units;
    uint32_t n, next, stop_at, width;
    int64_t *acc;
    uint64_t segments;
    int done_calls[64], inside, overlapped;
    volatile sig_atomic_t *stop;
    /* with trickle: units arrive one per 50 polls (as from MPI), and take
     * says "none yet" (-1) until then; poll must run on caller's thread */
    int trickle, polls, wrong_thread;
    uint32_t arrived;
    pthread_t caller;
} source;

static int src_take(void *ctx, rt_unit *u)
{
    source *S = ctx;
    if (S->stop && S->next == S->stop_at)
        *S->stop = 1;
    if (S->next == S->n)
        return 0;
    if (S->trickle && S->next == __atomic_load_n(&S->arrived, __ATOMIC_SEQ_CST))
        return -1;
    *u = S->units[S->next++];
    return 1;
}

static int src_poll(void *ctx, int idle)
{
    source *S = ctx;
    (void)idle;
    if (!pthread_equal(pthread_self(), S->caller))
        S->wrong_thread = 1;
    if (++S->polls % 50 || S->arrived == S->n)
        return 0;
    __atomic_add_fetch(&S->arrived, 1, __ATOMIC_SEQ_CST);
    return 1;
}

static void src_done(void *ctx, const rt_unit *u, const int64_t *sums, uint64_t segs)
{
    source *S = ctx;
    if (__atomic_add_fetch(&S->inside, 1, __ATOMIC_SEQ_CST) > 1)
        S->overlapped = 1;
    const size_t w = (size_t)(u->x1 - u->x0) * 3; /* a tile's rows are w values */
    for (uint32_t y = u->y0; y < u->y1; y++) {
        int64_t *dst = S->acc + ((size_t)y * S->width + u->x0) * 3;
        for (size_t i = 0; i < w; i++)
            dst[i] += sums[(y - u->y0) * w + i];
    }
    S->segments += segs;
    S->done_calls[u->id]++;
    __atomic_sub_fetch(&S->inside, 1, __ATOMIC_SEQ_CST);
}

int main(void)
{
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_final(&s, 5, 3), RT_OK);
    rt_accel *a;
    CHECK_EQ_INT(rt_accel_new(&a, &s, RT_ACCEL_BVH), RT_OK);
    rt_job p = {40, 24, 6, 20, 5, RT_DIFFUSE_LAMBERTIAN, RT_SAMPLER_SOBOL, 1, 0, 0, 0, RT_LIGHT_MIS};
    rt_renderer r;
    CHECK_EQ_INT(rt_render_init(&r, &s, a, &p), RT_OK);
    size_t n = (size_t)p.width * p.height * 3;
    int64_t *ref = calloc(n, sizeof *ref), *alt = calloc(n, sizeof *alt);
    uint64_t segs_ref = rt_render_rows(&r, 0, p.height, 0, p.samples, ref, 1);
    CHECK(segs_ref >= (uint64_t)p.width * p.height * p.samples);

    /* Bands of 5 rows, two threads. */
    uint64_t segs = 0;
    for (uint32_t y = 0; y < p.height; y += 5) {
        uint32_t y1 = y + 5 < p.height ? y + 5 : p.height;
        segs += rt_render_rows(&r, y, y1, 0, p.samples, alt + (size_t)y * p.width * 3, 2);
    }
    CHECK(memcmp(ref, alt, n * sizeof *ref) == 0);
    CHECK_EQ_U64(segs, segs_ref);

    /* Sample ranges 0-1, 1-4, 4-6 added in a scrambled order. */
    memset(alt, 0, n * sizeof *alt);
    rt_render_rows(&r, 0, p.height, 4, 6, alt, 2);
    rt_render_rows(&r, 0, p.height, 0, 1, alt, 1);
    rt_render_rows(&r, 0, p.height, 1, 4, alt, 3);
    CHECK(memcmp(ref, alt, n * sizeof *ref) == 0);

    /* A stream of units of every shape (rows, sample ranges, one row,
     * column tiles, the largest first, as the schedule hands them out): each
     * unit done once,
     * one done call at a time, the same image and segments for any thread
     * count (more threads than units in hand included). With trickle, the
     * units arrive only as the master thread polls (a worker's come by MPI)
     * and the other threads wait for them. */
    const uint32_t X = p.width;
    const rt_unit units[] = {{0, 0, 9, 0, 6, 0, X},   {1, 9, 15, 0, 2, 0, X},  {2, 9, 15, 2, 6, 0, X},
                             {3, 15, 16, 0, 6, 0, X}, {4, 16, 20, 0, 6, 0, X}, {5, 20, 22, 0, 5, 0, X},
                             {6, 22, 24, 0, 6, 0, 7}, {7, 20, 22, 5, 6, 0, X}, {8, 22, 24, 0, 6, 7, 29},
                             {9, 22, 24, 0, 6, 29, X}};
    const uint32_t n_units = sizeof units / sizeof units[0];
    for (int trickle = 0; trickle <= 1; trickle++)
        for (int threads = 1; threads <= 5; threads++) {
            memset(alt, 0, n * sizeof *alt);
            source S = {.units = units, .n = n_units, .width = p.width, .acc = alt, .trickle = trickle,
                        .caller = pthread_self()};
            rt_render_source src = {src_take, src_done, trickle ? src_poll : NULL, &S};
            CHECK_EQ_INT(rt_render_stream(&r, threads, &src), RT_OK);
            CHECK(memcmp(ref, alt, n * sizeof *ref) == 0);
            CHECK_EQ_U64(S.segments, segs_ref);
            int once = 1;
            for (uint32_t k = 0; k < n_units; k++)
                once &= S.done_calls[k] == 1;
            CHECK(once);
            CHECK_EQ_INT(S.overlapped, 0);
            CHECK_EQ_INT(S.next, n_units);
            if (trickle) { /* without a poll there is nothing to check here */
                CHECK_EQ_INT(S.wrong_thread, 0);
                CHECK(S.polls >= 50 * (int)n_units);
            }
        }
    /* A stop drops the units in hand: the unit taken as it came is never
     * done, nothing is taken after it, and a unit done before it is whole
     * (unit 0: its rows as in ref). One thread takes a unit only when those
     * in hand are all done, so there units 0 to 2 are done before the stop;
     * with more threads, which are is up to timing. */
    for (int threads = 1; threads <= 3; threads++) {
        volatile sig_atomic_t stop = 0;
        rt_renderer rs = r;
        rs.stop = &stop;
        memset(alt, 0, n * sizeof *alt);
        source S = {.units = units, .n = n_units, .stop_at = 3, .width = p.width, .acc = alt, .stop = &stop};
        rt_render_source src = {src_take, src_done, NULL, &S};
        CHECK_EQ_INT(rt_render_stream(&rs, threads, &src), RT_OK);
        CHECK_EQ_INT(stop, 1);
        CHECK_EQ_INT(S.next, 4); /* unit 3 was taken as the stop came, none after */
        CHECK_EQ_INT(S.done_calls[3], 0);
        if (threads == 1)
            CHECK_EQ_INT(S.done_calls[0] + S.done_calls[1] + S.done_calls[2], 3);
        if (S.done_calls[0])
            CHECK(memcmp(ref, alt, (size_t)9 * p.width * 3 * sizeof *ref) == 0);
    }

    /* Brute force gives the same image as the BVH. */
    rt_accel *brute;
    CHECK_EQ_INT(rt_accel_new(&brute, &s, RT_ACCEL_BRUTE), RT_OK);
    rt_renderer rb;
    CHECK_EQ_INT(rt_render_init(&rb, &s, brute, &p), RT_OK);
    memset(alt, 0, n * sizeof *alt);
    rt_render_rows(&rb, 0, p.height, 0, p.samples, alt, 2);
    CHECK(memcmp(ref, alt, n * sizeof *ref) == 0);

    /* A different seed gives a different image. */
    rt_job q = p;
    q.seed = 6;
    rt_renderer r2;
    CHECK_EQ_INT(rt_render_init(&r2, &s, a, &q), RT_OK);
    memset(alt, 0, n * sizeof *alt);
    rt_render_rows(&r2, 0, p.height, 0, p.samples, alt, 1);
    CHECK(memcmp(ref, alt, n * sizeof *ref) != 0);

    /* The rays a sample traces (bench_accel's input): as many as the
     * segments it counts, each from where the previous one hit. */
    rt_ray *path = malloc(p.max_depth * sizeof *path);
    CHECK(path != NULL);
    long total_rays = 0, total_segs = 0, chained = 1;
    for (uint32_t k = 0; k < 200; k++) {
        uint64_t segs = 0;
        rt_render_sample(&r, k % p.width, k % p.height, k, &segs);
        uint32_t m = rt_render_sample_rays(&r, k % p.width, k % p.height, k, path);
        total_rays += m;
        total_segs += (long)segs;
        for (uint32_t i = 1; i < m; i++) {
            rt_hit h;
            chained &= rt_accel_closest(a, &path[i - 1], 0.001, INFINITY, &h) &&
                       rt_v3_len(rt_v3_sub(rt_ray_at(&path[i - 1], h.t), path[i].orig)) == 0.0;
        }
    }
    CHECK_EQ_INT(total_rays, total_segs);
    CHECK(total_rays > 200);
    CHECK(chained);
    free(path);

    /* Tone mapping: the book's gamma 2 and 0.999 clamp. */
    int64_t px[6] = {0, (int64_t)(0.25 * RT_FIX_ONE) * 4, (int64_t)(4.0 * RT_FIX_ONE) * 4, 0, 0, 0};
    uint8_t out[6];
    rt_image_to_rgb8(px, 2, 4, out);
    CHECK_EQ_INT(out[0], 0);
    CHECK_EQ_INT(out[1], 128); /* sqrt(0.25) * 256 */
    CHECK_EQ_INT(out[2], 255); /* clamped to 0.999 */
    /* A wide layout (adaptive count, normal) to 3 sums of -s samples: the
     * colour scaled from each pixel's count (rounded half away from zero),
     * a signed buffer likewise, a pixel with no samples 0. */
    rt_job wj = {2, 1, 64, 8, 1, RT_DIFFUSE_LAMBERTIAN, RT_SAMPLER_SOBOL, 1, 0, 0.05, RT_AOV_NORMAL, RT_LIGHT_MIS};
    const rt_layout wl = rt_job_layout(&wj);
    CHECK_EQ_INT(wl.ch, 7);
    CHECK_EQ_INT(wl.count, 3);
    CHECK_EQ_INT(wl.normal, 4);
    CHECK_EQ_INT(wl.albedo, 0);
    const int64_t big = (int64_t)1 << 60; /* big * 64 needs more than 64 bits */
    int64_t wide[14] = {16, 17, big, 16, -16, -17, 0, 5, 6, 7, 0, 1, 2, 3};
    int64_t got[6];
    rt_image_extract(wide, 2, wl, 0, 64, got);
    CHECK_EQ_INT(got[0], 64);
    CHECK_EQ_INT(got[1], 68);
    CHECK_EQ_INT(got[2], big * 4); /* 2^60 * 64 / 16 */
    CHECK_EQ_INT(got[3] | got[4] | got[5], 0);
    rt_image_extract(wide, 2, wl, wl.normal, 64, got);
    CHECK_EQ_INT(got[0], -64);
    CHECK_EQ_INT(got[1], -68);
    CHECK_EQ_INT(got[2], 0);
    wide[3] = 48; /* 17 * 64 / 48 = 22.67: 23; -17 * 64 / 48: -23 */
    rt_image_extract(wide, 1, wl, 0, 64, got);
    CHECK_EQ_INT(got[1], 23);
    rt_image_extract(wide, 1, wl, wl.normal, 64, got);
    CHECK_EQ_INT(got[1], -23);
    CHECK_EQ_INT(rt_render_fix(-1.0), 0);
    CHECK_EQ_INT(rt_render_fix(NAN), 0);
    CHECK_EQ_INT(rt_render_fix(1e9), (int64_t)(RT_SAMPLE_MAX * RT_FIX_ONE));
    free(ref);
    free(alt);
    rt_accel_free(a);
    rt_accel_free(brute);
    rt_scene_free(&s);
    CHECK_DONE();
}
