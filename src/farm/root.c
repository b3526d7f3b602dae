/* root.c - rank 0's state (ledger, assembly, stats, error) and the verbs
 * its two threads use on it; each takes the lock itself and takes and
 * gives values. It calls neither the server nor rank0.c.
 *
 * Results are fixed-point sums (render.h), so the order in which they
 * arrive does not change a single bit of the image. */
#include "internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clock.h"
#include "mem.h"
#include "msg.h"
#include "policy.h"
#include "status.h"

/* Everything here is guarded by mu, but own, t0 and the schedule's shape,
 * which do not change after rt_root_new. */
struct rt_root {
    pthread_mutex_t mu;
    /* Rank 0's render thread waits on it when it has nothing to render
     * (rt_root_wait); broadcast wherever its take may stop saying -1: a
     * frame released, units requeued, an error, a stop, rt_root_wake. */
    pthread_cond_t more;
    int woken; /* rt_root_wake was called: the next wait returns */
    const rt_farm_rank0 *own; /* its image and hooks */
    rt_assembly as;
    rt_ledger led;
    double t0;          /* the render's time origin */
    double last_save;   /* when hooks.save last ran */
    uint32_t previewed; /* the last pass hooks.pass was called for */
    int error;          /* a status: rendering on rank 0 failed */
};

rt_root *rt_root_new(const rt_farm_job *job, const rt_farm_rank0 *own, int ranks, double t0, int *status)
{
    rt_root *R = calloc(1, sizeof *R);
    if (!R) {
        *status = RT_ENOMEM;
        return NULL;
    }
    pthread_mutex_init(&R->mu, NULL);
    pthread_cond_init(&R->more, NULL);
    R->own = own;
    R->t0 = R->last_save = t0;
    /* a frame job: one schedule of its frames' rows, the cap on frames in flight */
    rt_job whole = job->renderer->job;
    rt_sched_params p = job->sched;
    if (job->frames) {
        whole.height *= job->frames;
        p.frame_rows = job->renderer->job.height;
        p.frames_cap = RT_POLICY_FRAMES_IN_FLIGHT;
    }
    int st = rt_assembly_init(&R->as, &whole, &p, own->committed, own->acc, ranks, own->trace);
    if (!st && job->frames && (st = rt_assembly_frames(&R->as, own->frame_acc)) != RT_OK)
        rt_assembly_free(&R->as);
    if (!st && (st = rt_ledger_init(&R->led, &R->as.sched, ranks)) != RT_OK)
        rt_assembly_free(&R->as);
    if (st) {
        pthread_cond_destroy(&R->more);
        pthread_mutex_destroy(&R->mu);
        free(R);
        *status = st;
        return NULL;
    }
    *status = RT_OK;
    return R;
}

void rt_root_free(rt_root *R)
{
    if (!R)
        return;
    rt_assembly_free(&R->as);
    rt_ledger_free(&R->led);
    pthread_cond_destroy(&R->more);
    pthread_mutex_destroy(&R->mu);
    free(R);
}

/* Under mu: status (non-zero) becomes the error unless there is one; a
 * waiting render thread must see it. */
static void set_error(rt_root *R, int status)
{
    if (status && !R->error)
        R->error = status;
    pthread_cond_broadcast(&R->more);
}

uint32_t rt_root_units(const rt_root *R) { return R->as.sched.n_units; }

void rt_root_rows(rt_root *R, uint32_t *done, uint32_t *rows)
{
    pthread_mutex_lock(&R->mu);
    *done = R->as.sched.rows_done;
    *rows = R->as.sched.height;
    pthread_mutex_unlock(&R->mu);
}

void rt_root_add(rt_root *R, const rt_unit *u, const int64_t *sums, uint64_t segs, double start, double end)
{
    pthread_mutex_lock(&R->mu);
    int st = rt_ledger_done(&R->led, 0, u->id) && rt_ledger_in(&R->led, 0, u->id)
                 ? rt_assembly_add(&R->as, 0, u, sums, segs, start, end)
                 : RT_EINVAL;
    if (st)
        set_error(R, st);
    pthread_mutex_unlock(&R->mu);
}

void rt_root_fail(rt_root *R, int status)
{
    pthread_mutex_lock(&R->mu);
    R->error = status;
    pthread_cond_broadcast(&R->more);
    pthread_mutex_unlock(&R->mu);
}

void rt_root_wake(rt_root *R)
{
    pthread_mutex_lock(&R->mu);
    R->woken = 1;
    pthread_cond_broadcast(&R->more);
    pthread_mutex_unlock(&R->mu);
}

void rt_root_wait(rt_root *R)
{
    pthread_mutex_lock(&R->mu);
    while (!R->woken && !R->error && !RT_FARM_STOPPED() && rt_ledger_waiting(&R->led, &R->as.sched, 0))
        pthread_cond_wait(&R->more, &R->mu);
    R->woken = 0;
    pthread_mutex_unlock(&R->mu);
}

void rt_root_finish(rt_root *R, rt_farm_result *res)
{
    pthread_mutex_lock(&R->mu);
    R->as.stats[0].maxrss_mb = rt_sysinfo_peak_mb();
    rt_sysinfo_hostname(R->as.stats[0].host, sizeof R->as.stats[0].host);
    res->ranks = R->as.stats;
    res->segments = R->as.segments;
    res->trace = R->as.trace;
    res->n_trace = R->as.n_trace;
    R->as.stats = NULL; /* the caller's now */
    R->as.trace = NULL;
    pthread_mutex_unlock(&R->mu);
}

int rt_root_take(rt_root *R, int rank, rt_unit *u)
{
    pthread_mutex_lock(&R->mu);
    int got = RT_FARM_STOPPED() || R->error ? 0 : rt_ledger_take(&R->led, &R->as.sched, rank, u);
    if (got > 0 && R->as.facc) {
        /* a frame job: the unit's frame has its sums from now on */
        const uint32_t before = R->as.in_flight, k = rt_sched_frame(&R->as.sched, u->y0);
        int st = rt_assembly_open(&R->as, u, rt_now() - R->t0);
        if (st)
            set_error(R, st);
        const rt_farm_hooks *h = &R->own->hooks;
        if (R->as.in_flight > before && h->frame_open)
            h->frame_open(h->client, k);
    }
    pthread_mutex_unlock(&R->mu);
    return got;
}

/* A consistent copy of the committed counts and sums, taken under the lock
 * (other threads keep adding to the image). for_save clears the dirty
 * flag. The copy's pages are mapped up front (rt_mem_zeroed), so the copy
 * under the lock does not fault them in while the other threads wait for
 * it. Release with release(). */
static int snapshot(rt_root *R, int for_save, uint32_t **committed, int64_t **acc)
{
    size_t H = R->as.sched.height, n = rt_assembly_len(&R->as);
    *committed = malloc(H * sizeof **committed);
    *acc = rt_mem_zeroed(n * sizeof **acc);
    if (!*committed || !*acc) {
        free(*committed);
        rt_mem_free(*acc, n * sizeof **acc);
        return RT_ENOMEM;
    }
    pthread_mutex_lock(&R->mu);
    memcpy(*committed, R->as.sched.committed, H * sizeof **committed);
    memcpy(*acc, R->as.acc, n * sizeof **acc);
    if (for_save)
        R->as.dirty = 0;
    pthread_mutex_unlock(&R->mu);
    return RT_OK;
}

static void release(rt_root *R, uint32_t *committed, int64_t *acc)
{
    free(committed);
    rt_mem_free(acc, rt_assembly_len(&R->as) * sizeof *acc);
}

/* A frame job's frames in flight, copied under the lock as snapshot()
 * does; free with frames_release. */
typedef struct frames_copy {
    rt_farm_frames fr;
    uint32_t *index, *committed;
    int64_t **acc;
    size_t bytes; /* of a frame's sums */
} frames_copy;

static void frames_release(frames_copy *c)
{
    for (uint32_t i = 0; c->acc && i < c->fr.n; i++)
        rt_mem_free(c->acc[i], c->bytes);
    free(c->acc);
    free(c->index);
    free(c->committed);
}

/* Under mu: whether frame k is in flight for the checkpoint (it has sums
 * and is not complete: a complete one is the frame hook's, or will be). */
static int ckpt_frame(const rt_root *R, uint32_t k)
{
    return R->as.facc[k] && !rt_sched_frame_complete(&R->as.sched, k);
}

/* Under mu: how many frames are in flight (at most the cap). */
static uint32_t ckpt_frames(const rt_root *R)
{
    const rt_sched *sc = &R->as.sched;
    uint32_t n = 0;
    for (uint32_t k = sc->low; k < sc->frames && n < sc->cap; k++)
        n += ckpt_frame(R, k);
    return n;
}

/* The copy's buffers for n frames (pages mapped); RT_ENOMEM. */
static int frames_alloc(frames_copy *c, uint32_t n, uint32_t H)
{
    const size_t m = n ? n : 1; /* malloc(0) may be NULL */
    c->fr.n = n;
    c->index = malloc(m * sizeof *c->index);
    c->committed = malloc(m * H * sizeof *c->committed);
    c->acc = calloc(m, sizeof *c->acc);
    int ok = c->index && c->committed && c->acc;
    for (uint32_t i = 0; ok && i < n; i++)
        ok = (c->acc[i] = rt_mem_zeroed(c->bytes)) != NULL;
    return ok ? RT_OK : RT_ENOMEM;
}

/* Counts the frames in flight first, allocates that many copies (outside
 * the lock), then copies them under it; when more came in flight
 * meanwhile, it counts again. */
static int frames_snapshot(rt_root *R, frames_copy *c)
{
    const rt_sched *sc = &R->as.sched;
    const uint32_t H = sc->frame_rows;
    for (;;) {
        memset(c, 0, sizeof *c);
        c->bytes = rt_assembly_frame_bytes(&R->as);
        pthread_mutex_lock(&R->mu);
        const uint32_t want = ckpt_frames(R);
        pthread_mutex_unlock(&R->mu);
        if (frames_alloc(c, want, H) != RT_OK) {
            frames_release(c);
            return RT_ENOMEM;
        }
        pthread_mutex_lock(&R->mu);
        uint32_t n = ckpt_frames(R);
        if (n <= want) {
            n = 0;
            for (uint32_t k = sc->low; k < sc->frames && n < want; k++) {
                if (!ckpt_frame(R, k))
                    continue;
                c->index[n] = k;
                memcpy(c->committed + (size_t)n * H, sc->committed + (size_t)k * H, H * sizeof *c->committed);
                memcpy(c->acc[n++], R->as.facc[k], c->bytes);
            }
            R->as.dirty = 0;
        }
        pthread_mutex_unlock(&R->mu);
        if (n > want) {
            frames_release(c); /* more frames in flight now: again */
            continue;
        }
        for (uint32_t i = n; i < want; i++) { /* frames completed meanwhile */
            rt_mem_free(c->acc[i], c->bytes);
            c->acc[i] = NULL;
        }
        c->fr = (rt_farm_frames){.n = n, .index = c->index, .committed = c->committed, .acc = c->acc};
        return RT_OK;
    }
}

/* After each progressive pass but the last (the final image, which the
 * caller writes): a consistent image for hooks.pass. When the last passes
 * complete together (units of later passes came in before an early one),
 * the last but one is still shown: a progressive run always shows one. */
static void pass_hook(rt_root *R, uint32_t pass)
{
    const rt_farm_hooks *h = &R->own->hooks;
    if (pass >= R->as.sched.passes)
        pass = R->as.sched.passes - 1;
    if (!h->pass || pass == 0 || pass <= R->previewed)
        return;
    R->previewed = pass;
    uint32_t *committed;
    int64_t *acc;
    if (snapshot(R, 0, &committed, &acc) != RT_OK)
        return;
    h->pass(h->client, pass, rt_sched_pass_end(&R->as.sched, pass - 1), committed, acc);
    release(R, committed, acc);
}

/* hooks.save when due and something new was committed (or now, with
 * force), from a snapshot so that rendering goes on meanwhile. Returns
 * whether the state is saved. */
static int save_hook(rt_root *R, int force)
{
    const rt_farm_hooks *h = &R->own->hooks;
    if (R->as.facc ? !h->save_frames : !h->save)
        return 0;
    double now = rt_now();
    if (!force && now - R->last_save < h->save_interval)
        return 0;
    R->last_save = now;
    pthread_mutex_lock(&R->mu);
    int dirty = R->as.dirty;
    pthread_mutex_unlock(&R->mu);
    if (!dirty && !force)
        return 1;
    uint32_t *committed;
    int64_t *acc;
    frames_copy fc;
    int st;
    if (R->as.facc) {
        if (!(st = frames_snapshot(R, &fc))) {
            st = h->save_frames(h->client, &fc.fr);
            frames_release(&fc);
        }
    } else if (!(st = snapshot(R, 1, &committed, &acc))) {
        st = h->save(h->client, committed, acc);
        release(R, committed, acc);
    }
    if (st) {
        pthread_mutex_lock(&R->mu);
        R->as.dirty = 1;
        pthread_mutex_unlock(&R->mu);
    }
    return !st;
}

/* A frame job: the frames complete since the last call go to hooks.frame;
 * how many. */
static uint32_t frames_hook(rt_root *R)
{
    const rt_farm_hooks *h = &R->own->hooks;
    uint32_t n = 0;
    for (;;) {
        rt_farm_frame f;
        pthread_mutex_lock(&R->mu);
        int got = rt_assembly_next_frame(&R->as, &f, rt_now() - R->t0);
        pthread_mutex_unlock(&R->mu);
        if (!got)
            return n;
        n++;
        if (h->frame) {
            h->frame(h->client, &f);
        } else {
            rt_mem_free(f.acc, f.acc_bytes);
            free(f.trace);
        }
        /* Only now (the hook may have waited for the writer) does the frame
         * leave the cap: rank 0 holds at most the cap's frames and what
         * the hook keeps. */
        pthread_mutex_lock(&R->mu);
        rt_sched_release(&R->as.sched, f.index);
        pthread_cond_broadcast(&R->more); /* units of a later frame may be ready */
        pthread_mutex_unlock(&R->mu);
    }
}

uint32_t rt_root_tick(rt_root *R)
{
    const rt_farm_hooks *h = &R->own->hooks;
    const uint32_t frames = R->as.facc ? frames_hook(R) : 0;
    pthread_mutex_lock(&R->mu);
    uint64_t rows = R->as.sched.rows_done, segs = R->as.segments;
    uint32_t done = R->as.passes_done, passes = R->as.sched.passes;
    int ready = R->as.pass_ready;
    R->as.pass_ready = 0;
    pthread_mutex_unlock(&R->mu);
    if (h->progress)
        h->progress(h->client, done < passes ? done + 1 : done, rows, segs);
    if (ready)
        pass_hook(R, done);
    save_hook(R, 0);
    return frames;
}

int rt_root_save_now(rt_root *R) { return save_hook(R, 1); }


int rt_root_error(rt_root *R, int *complete)
{
    pthread_mutex_lock(&R->mu);
    *complete = rt_assembly_complete(&R->as);
    int err = R->error;
    pthread_mutex_unlock(&R->mu);
    return err;
}

uint32_t rt_root_assigned(rt_root *R, int rank)
{
    pthread_mutex_lock(&R->mu);
    uint32_t n = R->led.assigned[rank];
    pthread_mutex_unlock(&R->mu);
    return n;
}

uint32_t rt_root_held(rt_root *R, int rank)
{
    pthread_mutex_lock(&R->mu);
    uint32_t n = R->led.held[rank];
    pthread_mutex_unlock(&R->mu);
    return n;
}

int rt_root_frame_done(rt_root *R, uint32_t k)
{
    pthread_mutex_lock(&R->mu);
    int done = R->as.facc && rt_ledger_frame_done(&R->led, k);
    pthread_mutex_unlock(&R->mu);
    return done;
}

uint32_t rt_root_frames_peak(rt_root *R)
{
    pthread_mutex_lock(&R->mu);
    uint32_t n = R->as.in_flight_peak;
    pthread_mutex_unlock(&R->mu);
    return n;
}

int rt_root_pass_done(rt_root *R, uint32_t pass)
{
    pthread_mutex_lock(&R->mu);
    int done = pass + 1 < R->led.passes && rt_ledger_pass_done(&R->led, pass);
    pthread_mutex_unlock(&R->mu);
    return done;
}

uint32_t rt_root_lose(rt_root *R, int rank, double now, double heard, int *complete)
{
    pthread_mutex_lock(&R->mu);
    /* what the loss costs: the rendering of units it reported done but
     * whose sums it still held */
    const double redone = rt_ledger_held_sum(&R->led, rank, R->as.unit_secs);
    uint32_t back = rt_ledger_lose(&R->led, rank);
    if (back)
        pthread_cond_broadcast(&R->more); /* its units are ready again */
    rt_rank_stats *st = &R->as.stats[rank];
    st->lost = 1;
    st->lost_at = now - R->t0;
    st->silent = now - heard;
    st->redone = redone;
    st->units_redone = back;
    *complete = rt_assembly_complete(&R->as);
    pthread_mutex_unlock(&R->mu);
    return back;
}

int rt_root_report(rt_root *R, int rank, const rt_msg_report *rep)
{
    pthread_mutex_lock(&R->mu);
    int ok = rt_ledger_done(&R->led, rank, rep->id);
    if (ok)
        rt_assembly_account(&R->as, rank, rt_sched_unit(&R->as.sched, rep->id), rep->segs, rep->start, rep->end);
    pthread_mutex_unlock(&R->mu);
    return ok ? RT_OK : RT_EINVAL;
}

void rt_root_bounds(rt_root *R, rt_unit *bounds, uint32_t *max_ids, size_t *ch)
{
    /* the schedule's shape does not change after rt_assembly_init */
    const rt_sched *sc = &R->as.sched;
    *bounds = (rt_unit){.y1 = sc->height, .s1 = sc->samples, .x1 = sc->width};
    *max_ids = sc->n_units;
    *ch = R->as.row / sc->width;
}

int rt_root_sums(rt_root *R, int rank, const rt_msg_piece *pc)
{
    const rt_sched *sc = &R->as.sched;
    const rt_unit block = pc->block;
    uint64_t covered = 0;
    int ok = 1;
    for (size_t k = 0; ok && k < pc->n_ids; k++) {
        const rt_unit *u =
            pc->ids[k] >= 0 && pc->ids[k] <= UINT32_MAX ? rt_sched_unit(sc, (uint32_t)pc->ids[k]) : NULL;
        ok = u && u->y0 == block.y0 && u->y1 == block.y1 && u->x0 == block.x0 && u->x1 == block.x1 &&
             u->s0 >= block.s0 && u->s1 <= block.s1;
        covered += ok ? u->s1 - u->s0 : 0;
    }
    if (!ok || covered != block.s1 - block.s0)
        return RT_EFORMAT;
    pthread_mutex_lock(&R->mu);
    for (size_t k = 0; k < pc->n_ids; k++)
        if (!rt_ledger_in(&R->led, rank, (uint32_t)pc->ids[k])) {
            pthread_mutex_unlock(&R->mu);
            return RT_EINVAL;
        }
    int st = rt_assembly_sums(&R->as, &block, pc->sums, pc->n_ids);
    if (st)
        set_error(R, st);
    pthread_mutex_unlock(&R->mu);
    return RT_OK;
}

void rt_root_bye(rt_root *R, int rank, const rt_msg_bye *b)
{
    pthread_mutex_lock(&R->mu);
    rt_rank_stats *st = &R->as.stats[rank];
    st->wait = b->wait, st->comm = b->comm, st->maxrss_mb = b->peak_mb, st->held_mb = b->held_mb;
    pthread_mutex_unlock(&R->mu);
}

void rt_root_host(rt_root *R, int rank, const char *host)
{
    pthread_mutex_lock(&R->mu);
    snprintf(R->as.stats[rank].host, sizeof R->as.stats[rank].host, "%s", host);
    pthread_mutex_unlock(&R->mu);
}
