/* test_root.c - rank 0's render thread waiting for work (rt_root_wait) in
 * a frame job whose frames-in-flight cap is reached while another rank
 * holds the units: it blocks, and each event that may change what its take
 * says wakes it: a frame released (the other rank's last unit of the oldest
 * frame reported, its sums in, the main thread's tick), units requeued (the
 * other rank lost), an error on rank 0 (rt_root_fail, or a failing
 * rt_root_add through set_error), and rt_root_wake. A stop (signal) ends
 * the wait only through the server's rt_root_wake, which needs MPI
 * (server.c): here the stop is raised as a signal would, and the test
 * checks that a wait started after it does not block. Ranks are simulated
 * by calling root.c's verbs as server.c and rank0.c do; no MPI. A missing
 * wake-up fails the test after a timeout instead of hanging it. */
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <time.h>

#include "check.h"
#include "clock.h"
#include "internal.h"
#include "status.h"

/* 6 frames of 4 rows of 8 columns, bands of 2 rows: 2 units a frame, 12
 * in all; the cap (RT_POLICY_FRAMES_IN_FLIGHT, 4) binds at 8 units. */
enum { W = 8, FRAME_ROWS = 4, FRAMES = 6, S = 4, UNITS_OUT = 2 * RT_POLICY_FRAMES_IN_FLIGHT };

/* How long a waiter must stay blocked (no spurious return; not a speed
 * check), and how long a woken one may take to return before the test
 * calls the wake-up missing. */
#define BLOCKED_S 0.2
#define WOKEN_S 10.0

typedef struct waiter {
    rt_root *R;
    pthread_t th;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int returned;
    int stuck; /* it never returned: neither it nor its root is freed */
} waiter;

static void *wait_body(void *arg)
{
    waiter *w = arg;
    rt_root_wait(w->R);
    pthread_mutex_lock(&w->mu);
    w->returned = 1;
    pthread_cond_signal(&w->cv);
    pthread_mutex_unlock(&w->mu);
    return NULL;
}

static void waiter_start(waiter *w, rt_root *R)
{
    w->R = R;
    w->returned = w->stuck = 0;
    pthread_mutex_init(&w->mu, NULL);
    pthread_cond_init(&w->cv, NULL);
    if (pthread_create(&w->th, NULL, wait_body, w) != 0) {
        fprintf(stderr, "cannot start a thread\n");
        exit(1);
    }
}

/* Whether w's rt_root_wait has returned within secs; when it has, its
 * thread is joined. */
static int waiter_returned(waiter *w, double secs)
{
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += (time_t)secs;
    until.tv_nsec += (long)((secs - (double)(time_t)secs) * 1e9);
    if (until.tv_nsec >= 1000000000L) {
        until.tv_sec++;
        until.tv_nsec -= 1000000000L;
    }
    pthread_mutex_lock(&w->mu);
    while (!w->returned && pthread_cond_timedwait(&w->cv, &w->mu, &until) == 0)
        ;
    int back = w->returned;
    pthread_mutex_unlock(&w->mu);
    if (back) {
        pthread_join(w->th, NULL);
        pthread_cond_destroy(&w->cv);
        pthread_mutex_destroy(&w->mu);
    } else {
        w->stuck = 1;
    }
    return back;
}

/* Whether w is still blocked (it has not returned yet). */
static int waiter_blocked(waiter *w)
{
    pthread_mutex_lock(&w->mu);
    int blocked = !w->returned;
    pthread_mutex_unlock(&w->mu);
    return blocked;
}

static void sleep_s(double secs)
{
    struct timespec t = {.tv_sec = (time_t)secs, .tv_nsec = (long)((secs - (double)(time_t)secs) * 1e9)};
    while (nanosleep(&t, &t) != 0)
        ;
}

static const rt_job JOB = {.width = W,
                           .height = FRAME_ROWS,
                           .samples = S,
                           .max_depth = 8,
                           .seed = 1,
                           .diffuse = RT_DIFFUSE_LAMBERTIAN,
                           .sampler = RT_SAMPLER_SOBOL,
                           .roulette = 1};
static rt_renderer RENDERER;
static rt_farm_job FJOB;
static rt_farm_rank0 OWN; /* no hooks: a released frame's sums are freed */

/* A root and the units rank 1 took (frames 0 to 3, in order). */
typedef struct fixture {
    rt_root *R;
    rt_unit out[UNITS_OUT];
} fixture;

/* Zero sums for unit u (free them). */
static int64_t *zero_sums(rt_root *R, const rt_unit *u)
{
    rt_unit bounds;
    uint32_t max_ids;
    size_t ch;
    rt_root_bounds(R, &bounds, &max_ids, &ch);
    int64_t *sums = calloc(rt_unit_pixels(u) * ch, sizeof *sums);
    if (!sums)
        exit(1);
    return sums;
}

/* Rank 1 reports unit u done and sends its sums, as the server passes
 * them on. */
static void rank1_returns(rt_root *R, const rt_unit *u)
{
    rt_msg_report rep = {.id = u->id, .segs = 1, .start = 0, .end = 0};
    CHECK_EQ_INT(rt_root_report(R, 1, &rep), RT_OK);
    int64_t *sums = zero_sums(R, u);
    int64_t id = u->id;
    rt_msg_piece pc = {.block = *u, .ids = &id, .n_ids = 1, .sums = sums};
    CHECK_EQ_INT(rt_root_sums(R, 1, &pc), RT_OK);
    free(sums);
}

/* A root on 2 ranks where rank 1 took every unit the cap lets out and has
 * reported and sent the first unit of frame 0: rank 0's take says -1. */
static void fixture_init(fixture *fx)
{
    int st;
    fx->R = rt_root_new(&FJOB, &OWN, 2, rt_now(), &st);
    CHECK_EQ_INT(st, RT_OK);
    if (!fx->R)
        exit(1);
    CHECK_EQ_INT(rt_root_units(fx->R), 2 * FRAMES);
    for (int k = 0; k < UNITS_OUT; k++)
        CHECK_EQ_INT(rt_root_take(fx->R, 1, &fx->out[k]), 1);
    rt_unit u;
    CHECK_EQ_INT(rt_root_take(fx->R, 1, &u), -1);
    CHECK_EQ_INT(rt_root_take(fx->R, 0, &u), -1);
    CHECK_EQ_INT(fx->out[1].y1, FRAME_ROWS); /* frame 0's two units first */
    CHECK_EQ_INT(rt_root_assigned(fx->R, 1), UNITS_OUT);
    rank1_returns(fx->R, &fx->out[0]);
    CHECK_EQ_INT(rt_root_take(fx->R, 0, &u), -1); /* frame 0 is not complete */
}

enum { RELEASE, LOSE, FAIL, ADD_ERROR, WAKE, EVENTS };
static const char *const NAME[EVENTS] = {"frame released", "units requeued", "rt_root_fail", "rt_root_add error",
                                         "rt_root_wake"};

int main(void)
{
    RENDERER.job = JOB;
    FJOB = (rt_farm_job){.renderer = &RENDERER,
                         .frames = FRAMES,
                         .sched = {.band = 2,
                                   .max_band = 4,
                                   .ranks = 2,
                                   .units_per_rank = 1,
                                   .min_samples = 1,
                                   .passes = 1,
                                   .split = RT_SPLIT_COLUMNS}};
    fixture fx[EVENTS];
    waiter w[EVENTS];
    for (int e = 0; e < EVENTS; e++) {
        fixture_init(&fx[e]);
        waiter_start(&w[e], fx[e].R);
    }
    /* Every waiter blocks: its root's ledger still says "not yet". */
    sleep_s(BLOCKED_S);
    for (int e = 0; e < EVENTS; e++)
        if (!waiter_blocked(&w[e]))
            fprintf(stderr, "waiter of '%s' returned with nothing to wake it\n", NAME[e]);
    int blocked = 0;
    for (int e = 0; e < EVENTS; e++)
        blocked += waiter_blocked(&w[e]);
    CHECK_EQ_INT(blocked, EVENTS);

    rt_unit u;
    int complete;
    /* Frame released: rank 1's last unit of frame 0 comes back, the main
     * thread's tick hands the frame on; frame 4's units are ready. */
    rank1_returns(fx[RELEASE].R, &fx[RELEASE].out[1]);
    CHECK(rt_root_frame_done(fx[RELEASE].R, 0));
    CHECK_EQ_INT(rt_root_tick(fx[RELEASE].R), 1);
    CHECK_EQ_INT(waiter_returned(&w[RELEASE], WOKEN_S), 1);
    CHECK_EQ_INT(rt_root_take(fx[RELEASE].R, 0, &u), 1);
    CHECK_EQ_INT(u.y0, 4 * FRAME_ROWS);

    /* Units requeued: rank 1 is lost; its units (all but the one in) are
     * rank 0's to take. */
    CHECK_EQ_INT(rt_root_lose(fx[LOSE].R, 1, rt_now(), rt_now(), &complete), UNITS_OUT - 1);
    CHECK_EQ_INT(waiter_returned(&w[LOSE], WOKEN_S), 1);
    CHECK_EQ_INT(rt_root_take(fx[LOSE].R, 0, &u), 1);
    CHECK_EQ_INT(u.id, fx[LOSE].out[1].id); /* frame 0's second unit first */

    /* Rank 0's rendering fails (its render loop's status). */
    rt_root_fail(fx[FAIL].R, RT_EIO);
    CHECK_EQ_INT(waiter_returned(&w[FAIL], WOKEN_S), 1);
    CHECK_EQ_INT(rt_root_error(fx[FAIL].R, &complete), RT_EIO);
    CHECK_EQ_INT(rt_root_take(fx[FAIL].R, 0, &u), 0);

    /* Another thread of rank 0's team adds a unit rank 0 does not hold:
     * the error is kept (set_error). */
    int64_t *sums = zero_sums(fx[ADD_ERROR].R, &fx[ADD_ERROR].out[2]);
    rt_root_add(fx[ADD_ERROR].R, &fx[ADD_ERROR].out[2], sums, 1, 0, 0);
    free(sums);
    CHECK_EQ_INT(waiter_returned(&w[ADD_ERROR], WOKEN_S), 1);
    CHECK_EQ_INT(rt_root_error(fx[ADD_ERROR].R, &complete), RT_EINVAL);
    CHECK_EQ_INT(rt_root_take(fx[ADD_ERROR].R, 0, &u), 0);

    /* rt_root_wake: it returns though nothing changed; the wake-up is
     * used up, so the next wait blocks again. */
    rt_root *R = fx[WAKE].R;
    rt_root_wake(R);
    CHECK_EQ_INT(waiter_returned(&w[WAKE], WOKEN_S), 1);
    CHECK_EQ_INT(rt_root_take(R, 0, &u), -1);
    waiter again, stopped = {0};
    waiter_start(&again, R);
    sleep_s(BLOCKED_S);
    CHECK_EQ_INT(waiter_blocked(&again), 1);
    /* A stop: the signal sets the flag, the server wakes the waiter
     * (server.c), and from then on a wait returns at once and take hands
     * out nothing. */
    rt_farm_stop_raise(SIGTERM);
    rt_root_wake(R);
    CHECK_EQ_INT(waiter_returned(&again, WOKEN_S), 1);
    if (!again.stuck) {
        waiter_start(&stopped, R);
        CHECK_EQ_INT(waiter_returned(&stopped, WOKEN_S), 1);
        CHECK_EQ_INT(rt_root_take(R, 0, &u), 0);
    }
    if (stopped.stuck)
        fprintf(stderr, "a wait after the stop blocked\n");
    w[WAKE].stuck |= again.stuck | stopped.stuck;

    for (int e = 0; e < EVENTS; e++) {
        if (w[e].stuck)
            fprintf(stderr, "waiter of '%s' never returned\n", NAME[e]);
        else /* a stuck waiter still uses its root */
            rt_root_free(fx[e].R);
    }
    CHECK_DONE();
}
