/* run.h - one run of the program, as main tells it: what each step needs
 * and leaves behind. The steps live in checks.c (what rank 0 verifies
 * before anything renders), setup.c (scene, renderer, job and its hooks),
 * ckpt.c (the checkpoint from check to removal) and summary.c (image file,
 * summary, reports). */
#ifndef RT_RUN_H
#define RT_RUN_H

#include <stdint.h>
#include <time.h>

#include "accel.h"
#include "checkpoint.h"
#include "cli.h"
#include "farm.h"
#include "mem.h"
#include "primary.h"
#include "progress.h"
#include "render.h"
#include "scene.h"

typedef struct rt_run {
    double t_start;
    double setup;         /* seconds from the scene broadcast to the render's start */
    time_t start;         /* wall-clock start, for the reports */
    int argc;             /* the command line as given, for the reports */
    char **argv;
    rt_options opt;
    char ckpt_default[4096]; /* OUTPUT.ckpt when --checkpoint is not given */
    rt_farm farm;
    int root;             /* this is rank 0 */
    int threads, bound;   /* OpenMP threads of this rank; bound one to a CPU */
    rt_scene scene;       /* as broadcast, on every rank */
    uint64_t scene_hash;  /* of the broadcast bytes */
    rt_accel *accel;
    rt_primary *primary;  /* camera-ray lists (our BVH only), or NULL */
    rt_renderer renderer;
    rt_ckpt_id ckpt;      /* the checkpoint's identity of this job */
    rt_farm_job job;
    rt_farm_rank0 own;    /* rank 0: the framebuffer and hooks the farm gets */
    int64_t *acc;         /* rank 0: the framebuffer of sums */
    rt_mem_early fb;      /* its mapping, when it is mapped while the render starts */
    uint32_t *restored;   /* rank 0 on --resume: samples per row restored */
    uint32_t rows_restored;
    uint64_t samples_restored; /* sum over rows */
    int ckpt_warned;      /* a failed checkpoint write was reported */
    rt_progress progress;
    rt_farm_result res;
} rt_run;

/* checks.c: rank 0 checks the file system and the machine, every rank its
 * thread count; a non-zero exit code with err filled, or RT_EXIT_OK. */
rt_exit_code rt_run_check(rt_run *run, char *err, size_t errlen);

/* setup.c */
/* --dump-scene: rank 0 writes the scene as JSON; an exit code. */
int rt_run_dump_scene(const rt_options *o);
/* Rank 0 builds (or loads) the scene and every rank receives it; an exit
 * code, err filled on rank 0. */
int rt_run_scene(rt_run *run, char *err, size_t errlen);
/* Every rank: intersector, camera, camera-ray lists. Fails the job itself. */
void rt_run_renderer(rt_run *run);
/* The farm's job: units, threads, framebuffer, restored checkpoint, hooks.
 * Fails the job itself. */
void rt_run_job(rt_run *run);

/* ckpt.c: the checkpoint's life in a run. */
/* Rank 0: a writable path, there on --resume and not there otherwise; an
 * exit code, err filled. */
int rt_run_ckpt_check(const rt_options *o, char *err, size_t errlen);
/* Rank 0: the framebuffer of sums, the checkpoint's rows restored into it
 * on --resume. Fails the job itself. */
void rt_run_ckpt_framebuffer(rt_run *run);
/* The farm's save hook (ctx: the run). */
int rt_run_ckpt_save(void *ctx, const uint32_t *committed, const int64_t *acc);
/* The whole render into the checkpoint (the image could not be written). */
int rt_run_ckpt_keep_render(const rt_run *run);
/* The image is written: remove the checkpoint, or keep it complete. */
void rt_run_ckpt_done(const rt_run *run);

/* summary.c: rank 0 after the render: the image file, the checkpoint
 * (removed or kept), the summary on stdout, --stats and --trace. */
void rt_run_finish(rt_run *run);
/* The three values at `first` of every pixel of acc (the colour 0, or an
 * AOV, run->renderer.lay) as 3 sums per pixel of the job's samples
 * (rt_image_extract); NULL when out of memory. Free with rt_mem_free. */
int64_t *rt_run_values(const rt_run *run, const int64_t *acc, uint32_t first);

void rt_run_free(rt_run *run);

#endif
