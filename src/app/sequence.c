/* sequence.c - a frame job (issue 37): the frames of the range in turn,
 * over the scene, renderer and farm that setup built once. Each frame's
 * camera and time come from its number alone (rt_run_frame_camera, on every
 * rank: nothing per frame is broadcast), so a frame is the same bytes in a
 * range or alone (--frame N). A finished frame is its file; the checkpoint
 * lives for the whole job (kept complete after each frame, so that it is
 * there whenever the job stops) and holds the frame in flight; --resume
 * skips the frames whose files exist and continues the checkpoint's.
 * Rank 0 hands each rendered frame to its writer thread (writer.c) and
 * serves the next frame's units at once. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "clock.h"
#include "mem.h"
#include "run.h"
#include "status.h"

/* Rank 0 on --resume: the frame the checkpoint holds, once it is known to
 * be this job's (another job's is refused, as for one image). */
static uint32_t resumed_frame(const rt_options *o, const rt_run_rank *rank, const rt_run_setup *s)
{
    char why[512] = "";
    uint32_t frame = 0;
    int st = rt_ckpt_frame(o->checkpoint, &frame, why, sizeof why);
    if (!st) {
        rt_options fo = *o;
        fo.frame = frame;
        const rt_ckpt_id id = rt_run_ckpt_id(&fo, s);
        st = rt_ckpt_check(o->checkpoint, &id, why, sizeof why);
    }
    if (st)
        rt_farm_fail(&rank->farm, RT_EXIT_CHECKPOINT, "--resume: cannot use checkpoint '%s': %s", o->checkpoint,
                     why[0] ? why : rt_status_str(st));
    return frame;
}

/* The range so far, for the progress line and its ETA over the whole range. */
typedef struct range {
    double t0;              /* the job's start */
    uint32_t index, frames; /* this frame's place in the range */
    uint64_t base_rows;     /* rows done before this run: skipped frames, restored rows */
    uint64_t segments;      /* of the frames rendered so far */
} range;

/* Frame `frame` with the frame's options fo (its files in paths):
 * rendered, then handed to rank 0's writer w. */
static void render_frame(rt_run *run, const rt_options *fo, const rt_frame_paths *paths, rt_run_writer *w, int last,
                         range *g)
{
    rt_run_rank *rank = &run->rank;
    rt_run_setup *setup = &run->setup;
    const double t0 = rt_now();
    rt_run_frame_camera(fo, rank, setup, fo->frame);
    if (rank->root) {
        rt_run_writer_hold(w);
        rt_run_root_init(fo, rank, setup, &run->root);
        run->root.writer = w; /* joined before a signal's exit */
        rt_progress *p = &run->root.progress;
        const uint64_t h = fo->job.height;
        g->base_rows += run->root.rows_restored;
        *p = (rt_progress){.enabled = p->enabled, .tty = p->tty, .t0 = g->t0, .last = p->last,
                           .total_rows = h * g->frames, .base_rows = g->base_rows, .pass = 1, .passes = 1,
                           .offset_rows = h * g->index, .offset_segments = g->segments, .frame_rows = h,
                           .frame_index = g->index, .frames = g->frames};
    }
    run->result.setup = rt_now() - t0;
    rt_farm_render(&rank->farm, &setup->job, rank->root ? &run->root.own : NULL, &run->result.farm);
    rt_mem_settle(&run->root.fb);
    if (rank->root) {
        rt_progress_finish(&run->root.progress, run->result.farm.segments);
        g->segments += run->result.farm.segments;
        rt_run_writer_put(w, &run->cmd, fo, paths, &run->root, &run->result, last);
    }
    rt_run_release(&run->root, &run->result); /* what the frame's render left */
}

void rt_run_frames(rt_run *run)
{
    const rt_options *o = &run->cmd.opt;
    const rt_run_rank *rank = &run->rank;
    const uint32_t n = rt_frames_count(&o->frames);
    uint32_t resume = UINT32_MAX;
    range g = {.t0 = rt_now(), .frames = n};
    if (rank->root && o->resume)
        resume = resumed_frame(o, rank, &run->setup);
    rt_frame_paths *paths = malloc(sizeof *paths);
    if (!paths)
        rt_farm_fail(&rank->farm, RT_EXIT_RUNTIME, "out of memory");
    rt_run_writer *w = rank->root ? rt_run_writer_start(rank, &run->setup) : NULL;
    for (uint32_t i = 0; i < n; i++) {
        rt_options fo;
        const uint32_t frame = rt_frames_at(&o->frames, i);
        if (rt_cli_frames_paths(o, frame, &fo, paths) != RT_OK) /* checked before: cannot fail */
            rt_farm_fail(&rank->farm, RT_EXIT_RUNTIME, "frame %u: file name too long", frame);
        int skip = rank->root && o->resume && access(fo.output, F_OK) == 0; /* written: temp + rename */
        rt_farm_bcast_int(&rank->farm, &skip);
        g.index = i;
        if (skip) {
            g.base_rows += o->job.height;
            if (rank->root && !o->quiet)
                fprintf(stderr, "rt-mpi: frame %u: %s is written, skipped (--resume)\n", frame, fo.output);
            continue;
        }
        fo.resume = o->resume && frame == resume;
        fo.keep_checkpoint = 1; /* removed once the last frame is written */
        fo.done_file = i + 1 < n ? NULL : o->done_file;
        render_frame(run, &fo, paths, w, i + 1 == n, &g);
    }
    free(paths);
    /* Every file written (the done file is the last frame's, after all
     * of them), or a failed write's line and exit code, before the
     * checkpoint goes. */
    if (w)
        rt_run_writer_finish(w);
    if (rank->root && o->checkpoint && !o->keep_checkpoint)
        unlink(o->checkpoint);
}
