/* ckpt.c - the checkpoint's life in a run (its format: io/checkpoint.c):
 * checked before anything renders, restored into the framebuffer on
 * --resume, saved by the farm's save hook while the render goes on, kept
 * with the whole render if the image cannot be written, and removed (or
 * kept, --keep-checkpoint) once the image is written. */
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "mem.h"
#include "run.h"
#include "status.h"

/* The checkpoint: a writable path, there on --resume, not there otherwise
 * (a leftover would be clobbered, or silently ignored). */
rt_exit_code rt_run_ckpt_check(const rt_options *o, char *err, size_t errlen)
{
    if (rt_cli_check_path("--checkpoint", o->checkpoint, err, errlen) != RT_OK)
        return RT_EXIT_USAGE;
    if (o->resume && access(o->checkpoint, F_OK) != 0) {
        snprintf(err, errlen, "--resume: no checkpoint '%s' to resume from", o->checkpoint);
        return RT_EXIT_CHECKPOINT;
    }
    if (!o->resume && access(o->checkpoint, F_OK) == 0) {
        snprintf(err, errlen,
                 "checkpoint '%s' exists: pass --resume to continue that render, or delete it to start over",
                 o->checkpoint);
        return RT_EXIT_CHECKPOINT;
    }
    return RT_EXIT_OK;
}

/* Rank 0 owns the framebuffer of sums; a resumed run starts from the
 * checkpoint's rows. */
void rt_run_ckpt_framebuffer(const rt_options *o, const rt_farm *f, rt_run_root *r)
{
    r->acc_len = (size_t)o->job.width * o->job.height * rt_job_layout(&o->job).ch;
    /* A fresh framebuffer is mapped while the render starts (mem.h); a
     * checkpoint is read into every page of it first anyway. */
    if (o->resume) {
        r->acc = rt_mem_zeroed(r->acc_len * sizeof *r->acc);
    } else {
        rt_mem_zeroed_early(&r->fb, r->acc_len * sizeof *r->acc);
        r->acc = r->fb.p;
    }
    if (!r->acc)
        rt_farm_fail(f, RT_EXIT_RUNTIME, "out of memory for the %u x %u framebuffer", o->job.width, o->job.height);
    if (!o->resume)
        return;
    char err[1024] = "";
    r->restored = calloc(o->job.height, sizeof *r->restored);
    if (!r->restored)
        rt_farm_fail(f, RT_EXIT_RUNTIME, "out of memory");
    int st = rt_ckpt_read(o->checkpoint, &r->ckpt, r->restored, r->acc, &r->rows_restored, err, sizeof err);
    if (st)
        rt_farm_fail(f, RT_EXIT_CHECKPOINT, "--resume: cannot use checkpoint '%s': %s", o->checkpoint,
                     err[0] ? err : rt_status_str(st));
    for (uint32_t y = 0; y < o->job.height; y++)
        r->samples_restored += r->restored[y];
}

int rt_run_ckpt_save(rt_farm_client *c, const uint32_t *committed, const int64_t *acc)
{
    const char *path = c->opt->checkpoint;
    int st = rt_ckpt_write(path, &c->root->ckpt, committed, acc);
    if (st && !c->root->ckpt_warned)
        fprintf(stderr, "rt-mpi: warning: cannot write checkpoint %s: %s (rendering goes on; will retry)\n", path,
                rt_status_str(st));
    c->root->ckpt_warned |= st != RT_OK;
    return st;
}

/* A checkpoint that holds the whole finished image (every row complete). */
static int save_finished(const rt_options *o, const rt_run_root *r)
{
    const rt_job *j = &o->job;
    uint32_t *all = malloc(j->height * sizeof *all);
    if (!all)
        return RT_ENOMEM;
    for (uint32_t y = 0; y < j->height; y++)
        all[y] = j->samples;
    int st = rt_ckpt_write(o->checkpoint, &r->ckpt, all, r->acc);
    free(all);
    return st;
}

int rt_run_ckpt_keep_render(const rt_options *o, const rt_run_root *r)
{
    return o->checkpoint ? save_finished(o, r) : RT_EINVAL;
}

void rt_run_ckpt_done(const rt_options *o, const rt_run_root *r)
{
    int st;
    if (!o->checkpoint)
        return;
    if (!o->keep_checkpoint)
        unlink(o->checkpoint);
    else if ((st = save_finished(o, r)) != RT_OK)
        fprintf(stderr, "rt-mpi: warning: cannot write checkpoint %s: %s\n", o->checkpoint, rt_status_str(st));
}
