/* sequence.c - a frame job (issue 37): the frames of the range still to
 * render as one farm render over the scene, intersector and farm that setup
 * built once. The farm schedules their rows as one image of frames x
 * height rows (units never cross a frame, at most RT_POLICY_FRAMES_IN_FLIGHT
 * frames in flight), so no rank waits at the end of a frame while a later
 * one has work. Every rank renders a unit with its frame's renderer, made
 * from the frame's number alone (rt_run_frame_renderer: nothing per frame
 * is broadcast), so a frame is the same bytes in a range or alone (--frame
 * N). Rank 0 hands each frame to its writer thread (writer.c) as soon as
 * its last sums are in. A finished frame is its file; the checkpoint holds
 * the frames in flight (format 8) and --resume skips the frames whose
 * files exist, restores those in flight and renders the rest. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "clock.h"
#include "mem.h"
#include "run.h"
#include "status.h"

/* The frame job's state: which frames render, the ring of frame renderers
 * (every rank), and rank 0's restored counts and writer. */
typedef struct rt_run_seq {
    rt_run *run;
    uint32_t n;       /* frames of the range */
    uint32_t F;       /* to render: todo[index] is the frame's number */
    uint32_t skipped; /* written before (--resume) */
    uint32_t *todo;
    rt_renderer ring[RT_FARM_RING]; /* job.frame_renderer's slots */
    rt_run_cam_lists lists[RT_FARM_RING];
    /* rank 0 */
    rt_run_writer *w;
    rt_frame_paths *paths;      /* a frame's files, for the hand-over */
    uint32_t *rows_restored;    /* per index: complete rows restored */
    uint64_t *samples_restored; /* per index */
    int64_t **facc;             /* per index: restored sums, taken by the farm */
    uint32_t completed;
    int ckpt_warned;
} rt_run_seq;

static void *alloc(const rt_run_seq *q, size_t n, size_t size)
{
    void *p = calloc(n ? n : 1, size);
    if (!p)
        rt_farm_fail(&q->run->rank.farm, RT_EXIT_RUNTIME, "out of memory");
    return p;
}

/* frame's options and files (in q->paths) as fo. */
static void frame_options(rt_run_seq *q, uint32_t frame, rt_options *fo)
{
    if (rt_cli_frames_paths(&q->run->cmd.opt, frame, fo, q->paths) != RT_OK) /* checked before: cannot fail */
        rt_farm_fail(&q->run->rank.farm, RT_EXIT_RUNTIME, "frame %u: file name too long", frame);
}

/* Rank 0 decides which frames render (with --resume, those whose files do
 * not exist: written through temp + rename, an existing file is complete);
 * every rank gets the list. */
static void plan(rt_run_seq *q)
{
    const rt_options *o = &q->run->cmd.opt;
    const rt_farm *f = &q->run->rank.farm;
    uint8_t *buf = NULL;
    size_t len = 0;
    if (q->run->rank.root) {
        q->todo = alloc(q, q->n, sizeof *q->todo);
        for (uint32_t i = 0; i < q->n; i++) {
            rt_options fo;
            const uint32_t frame = rt_frames_at(&o->frames, i);
            frame_options(q, frame, &fo);
            if (o->resume && access(fo.output, F_OK) == 0) {
                q->skipped++;
                if (!o->quiet)
                    fprintf(stderr, "rt-mpi: frame %u: %s is written, skipped (--resume)\n", frame, fo.output);
            } else {
                q->todo[q->F++] = frame;
            }
        }
        buf = (uint8_t *)q->todo;
        len = (size_t)q->F * sizeof *q->todo;
    }
    int F = (int)q->F, skipped = (int)q->skipped;
    rt_farm_bcast_int(f, &F);
    rt_farm_bcast_int(f, &skipped);
    q->F = (uint32_t)F, q->skipped = (uint32_t)skipped;
    if (F)
        rt_farm_bcast_bytes(f, &buf, &len);
    q->todo = (uint32_t *)buf;
    /* every frame's camera, before anything renders: a degenerate one is
     * bad input (exit 2), as the first frame's is */
    for (uint32_t k = 0; k < q->F; k++) {
        rt_renderer r = q->run->setup.renderer;
        rt_camera_desc cam;
        double t0, t1;
        int st = rt_anim_frame(&q->run->setup.scene, &o->anim, q->todo[k], &cam, &t0, &t1);
        if (!st)
            st = rt_render_frame(&r, &cam, t0, t1);
        if (st)
            rt_farm_fail(f, RT_EXIT_USAGE, "frame %u: camera: %s", q->todo[k], rt_status_str(st));
    }
}

/* The farm's frame_renderer: slot gets frame index's renderer (units.c
 * checks that the slot's former frame has no unit in hand). */
static int frame_renderer(void *ctx, uint32_t slot, uint32_t index, const rt_renderer **r)
{
    rt_run_seq *q = ctx;
    int st = rt_run_frame_renderer(&q->run->cmd.opt, &q->run->setup, q->todo[index], &q->ring[slot], &q->lists[slot]);
    *r = &q->ring[slot];
    return st;
}

/* Rank 0 on --resume: the checkpoint's frames, once it is known to be this
 * job's (another job's is refused, exit 3, as for one image); those still
 * to render are restored into committed and q->facc, the others (their
 * files exist) dropped. */
static void restore(rt_run_seq *q, uint32_t *committed)
{
    const rt_options *o = &q->run->cmd.opt;
    const rt_run_root *r = &q->run->root;
    const uint32_t H = o->job.height;
    const size_t bytes = (size_t)H * o->job.width * rt_job_layout(&o->job).ch * sizeof(int64_t);
    char why[512] = "";
    uint32_t n = 0, rows = 0, *frames = alloc(q, RT_CKPT_MAX_FRAMES, sizeof *frames);
    int st = rt_ckpt_frames(o->checkpoint, &n, frames, RT_CKPT_MAX_FRAMES, why, sizeof why);
    uint32_t *counts = st ? NULL : alloc(q, (size_t)n * H, sizeof *counts);
    int64_t **acc = st ? NULL : alloc(q, n, sizeof *acc);
    for (uint32_t i = 0; !st && i < n; i++)
        if (!(acc[i] = rt_mem_zeroed(bytes)))
            st = RT_ENOMEM;
    if (!st)
        st = rt_ckpt_read_frames(o->checkpoint, &r->ckpt, n, counts, acc, &rows, why, sizeof why);
    if (st)
        rt_farm_fail(&q->run->rank.farm, RT_EXIT_CHECKPOINT, "--resume: cannot use checkpoint '%s': %s",
                     o->checkpoint, why[0] ? why : rt_status_str(st));
    for (uint32_t i = 0; i < n; i++) {
        uint32_t k = 0;
        while (k < q->F && q->todo[k] != frames[i])
            k++;
        if (k == q->F || q->facc[k]) { /* written (files decide), or listed twice */
            rt_mem_free(acc[i], bytes);
            continue;
        }
        q->facc[k] = acc[i];
        for (uint32_t y = 0; y < H; y++) {
            const uint32_t c = counts[(size_t)i * H + y];
            committed[(size_t)k * H + y] = c;
            q->rows_restored[k] += c == o->job.samples;
            q->samples_restored[k] += c;
        }
    }
    free(acc);
    free(counts);
    free(frames);
}

/* ---- rank 0's hooks ------------------------------------------------------ */

static int save_frames(rt_farm_client *c, const rt_farm_frames *fr)
{
    rt_run_seq *q = c->seq;
    uint32_t numbers[RT_POLICY_FRAMES_IN_FLIGHT];
    for (uint32_t i = 0; i < fr->n && i < RT_POLICY_FRAMES_IN_FLIGHT; i++)
        numbers[i] = q->todo[fr->index[i]];
    const char *path = c->opt->checkpoint;
    int st = fr->n > RT_POLICY_FRAMES_IN_FLIGHT
                 ? RT_EINVAL
                 : rt_ckpt_write_frames(path, &c->root->ckpt, fr->n, numbers, fr->committed,
                                        (const int64_t *const *)fr->acc);
    if (st && !q->ckpt_warned)
        fprintf(stderr, "rt-mpi: warning: cannot write checkpoint %s: %s (rendering goes on; will retry)\n", path,
                rt_status_str(st));
    q->ckpt_warned |= st != RT_OK;
    return st;
}

static void frame_open(rt_farm_client *c, uint32_t index)
{
    (void)index;
    rt_run_writer_hold(c->seq->w);
}

/* Frame f->index is complete: to the writer thread (its sums, stats and
 * trace move there), while rank 0 serves on. */
static void on_frame(rt_farm_client *c, rt_farm_frame *f)
{
    rt_run_seq *q = c->seq;
    rt_options fo;
    frame_options(q, q->todo[f->index], &fo);
    fo.keep_checkpoint = 1; /* the checkpoint is the main thread's */
    fo.done_file = NULL;    /* written once every frame is */
    rt_run_root root = {.acc = f->acc,
                        .acc_len = f->acc_bytes / sizeof *f->acc,
                        .rows_restored = q->rows_restored[f->index],
                        .samples_restored = q->samples_restored[f->index]};
    rt_run_result res = {.farm = {.segments = f->segments,
                                  .units = f->units,
                                  .wall = f->last - f->first,
                                  .start = f->first,
                                  .trace = f->trace,
                                  .n_trace = f->n_trace}};
    rt_progress *p = &c->root->progress;
    const uint32_t done = q->skipped + ++q->completed;
    p->frame_index = done < q->n ? done : q->n - 1;
    rt_run_writer_put(q->w, &q->run->cmd, &fo, q->paths, &root, &res, f->index + 1 == q->F);
}

/* Rank 0's part before the render: identity, restored frames, progress
 * line, hooks, writer. */
static void root_init(rt_run_seq *q)
{
    const rt_options *o = &q->run->cmd.opt;
    rt_run_root *r = &q->run->root;
    const uint32_t H = o->job.height;
    q->rows_restored = alloc(q, q->F, sizeof *q->rows_restored);
    q->samples_restored = alloc(q, q->F, sizeof *q->samples_restored);
    q->facc = alloc(q, q->F, sizeof *q->facc);
    r->restored = alloc(q, (size_t)q->F * H, sizeof *r->restored); /* freed with the run */
    if (o->resume)
        restore(q, r->restored);
    q->w = rt_run_writer_start(&q->run->rank, &q->run->setup);
    r->writer = q->w; /* joined before a signal's exit */
    uint64_t restored_rows = 0;
    for (uint32_t k = 0; k < q->F; k++) {
        restored_rows += q->rows_restored[k];
        if (q->facc[k])
            rt_run_writer_hold(q->w); /* in flight from the start */
    }
    rt_progress_init(&r->progress, (uint64_t)H * q->n, o->quiet);
    r->progress.offset_rows = (uint64_t)H * q->skipped;
    r->progress.base_rows = r->progress.offset_rows + restored_rows;
    r->progress.frame_rows = (uint64_t)H * q->F;
    r->progress.pass = r->progress.passes = 1;
    r->progress.frames = q->n;
    r->progress.frame_index = q->skipped < q->n ? q->skipped : q->n - 1;
    r->client = (rt_farm_client){.opt = o, .lay = q->run->setup.renderer.lay, .root = r, .seq = q};
    r->own = (rt_farm_rank0){.committed = r->restored, .frame_acc = q->facc, .trace = o->trace != NULL,
                             .hooks = rt_run_hooks(r)};
    r->own.hooks.frame = on_frame;
    r->own.hooks.frame_open = frame_open;
    if (o->checkpoint) {
        r->own.hooks.save_frames = save_frames;
        r->own.hooks.save_interval = o->checkpoint_interval;
    }
    if (!o->quiet) {
        char what[96];
        snprintf(what, sizeof what, "frames %u-%u:%u (%u to render), ", o->frames.first, o->frames.last,
                 o->frames.step, q->F);
        rt_run_say_start(o, &q->run->rank, &q->run->setup, what);
    }
}

void rt_run_frames(rt_run *run)
{
    const rt_options *o = &run->cmd.opt;
    const rt_run_rank *rank = &run->rank;
    rt_run_seq q = {.run = run, .n = rt_frames_count(&o->frames)};
    q.paths = alloc(&q, 1, sizeof *q.paths);
    if (rank->root) {
        char why[512] = "";
        run->root.ckpt = rt_run_ckpt_id(o, &run->setup);
        int st = o->resume ? rt_ckpt_check(o->checkpoint, &run->root.ckpt, why, sizeof why) : RT_OK;
        if (st) /* another job's checkpoint: refused before anything renders, as for one image */
            rt_farm_fail(&rank->farm, RT_EXIT_CHECKPOINT, "--resume: cannot use checkpoint '%s': %s", o->checkpoint,
                         why[0] ? why : rt_status_str(st));
    }
    plan(&q);
    if (q.F) {
        rt_farm_job *job = &run->setup.job;
        job->frames = q.F;
        job->frame_renderer = frame_renderer;
        job->frame_ctx = &q;
        if (rank->root)
            root_init(&q);
        rt_farm_render(&run->rank.farm, job, rank->root ? &run->root.own : NULL, &run->result.farm);
    }
    if (rank->root) {
        rt_progress_finish(&run->root.progress, run->result.farm.segments);
        /* Every file written (or a failed write's line and exit code),
         * then the range's totals, the done file, and the checkpoint goes. */
        uint64_t hash = 0;
        uint32_t peak = 0;
        if (q.w) {
            run->root.writer = NULL;
            rt_run_writer_finish(q.w, &hash, &peak);
        }
        if (q.F)
            rt_run_range_summary(&run->cmd, rank, &run->result.farm, q.F, q.skipped, peak);
        if (o->done_file) {
            rt_options fo;
            frame_options(&q, o->frames.last, &fo);
            rt_run_write_done(o->done_file, hash, run->result.farm.lost, fo.output);
        }
        /* nothing in flight any more: kept (--keep-checkpoint), it holds no frame */
        if (o->checkpoint && !o->keep_checkpoint)
            unlink(o->checkpoint);
        else if (o->checkpoint && rt_ckpt_write_frames(o->checkpoint, &run->root.ckpt, 0, NULL, NULL, NULL))
            fprintf(stderr, "rt-mpi: warning: cannot write checkpoint %s\n", o->checkpoint);
    }
    for (uint32_t i = 0; i < RT_FARM_RING; i++)
        rt_run_cam_lists_free(&q.lists[i]);
    free(q.todo);
    free(q.paths);
    free(q.rows_restored);
    free(q.samples_restored);
    free(q.facc);
}
