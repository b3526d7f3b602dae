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
#include "world.h"
#include "progress.h"
#include "render.h"
#include "scene.h"

/* A run in parts, so that each step takes only what it reads or fills. A
 * run renders one frame today; what is per frame (rt_run_root, rt_run_result)
 * is kept apart from what is per job (rt_run_cmd, rt_run_rank, rt_run_setup),
 * so that a job of several frames can repeat the former over the latter. */

/* What the command line says (and when it was given); read-only once
 * rt_run_check has settled the checkpoint's default path. */
typedef struct rt_run_cmd {
    int argc;             /* the command line as given, for the reports */
    char **argv;
    double t_start;       /* rt_now() at the start, for the total wall time */
    time_t start;         /* wall-clock start, for the reports */
    rt_options opt;
    char ckpt_default[4096]; /* OUTPUT.ckpt when --checkpoint is not given */
} rt_run_cmd;

/* This process in the farm: its rank and its threads. */
typedef struct rt_run_rank {
    rt_farm farm;
    int root;             /* this is rank 0 */
    int threads, bound;   /* OpenMP threads of this rank; bound one to a CPU */
} rt_run_rank;

/* A camera's candidate lists for its camera rays (our BVH only): book 1's
 * over the spheres (primary.h) or the book-2 loop's over the world
 * (world.h), or neither (NULL). */
typedef struct rt_run_cam_lists {
    rt_primary *primary;
    rt_world_lists *world;
} rt_run_cam_lists;

/* Frees l's lists (NULL after). */
static inline void rt_run_cam_lists_free(rt_run_cam_lists *l)
{
    rt_primary_free(l->primary);
    rt_world_lists_free(l->world);
    l->primary = NULL;
    l->world = NULL;
}

/* What setup builds, the same on every rank. */
typedef struct rt_run_setup {
    rt_scene scene;       /* as broadcast */
    uint64_t scene_hash;  /* of the broadcast bytes */
    rt_accel *accel;
    rt_run_cam_lists lists; /* the camera's (frame 0's in a frame job: none) */
    rt_renderer renderer;
    rt_farm_job job;
} rt_run_setup;

/* The farm's hooks' context (farm.h declares it, opaque to the farm): what
 * they read of the run and rank 0's own state they update. */
struct rt_farm_client {
    const rt_options *opt;
    rt_layout lay;
    struct rt_run_root *root;
    struct rt_run_seq *seq; /* a frame job's state (sequence.c), or NULL */
};

/* Rank 0's own: the image it gathers and what it does meanwhile. */
typedef struct rt_run_root {
    rt_ckpt_id ckpt;      /* the checkpoint's identity of this image */
    int ckpt_warned;      /* a failed checkpoint write was reported */
    int64_t *acc;         /* the framebuffer of sums */
    size_t acc_len;       /* its values */
    rt_mem_early fb;      /* its mapping, when it is mapped while the render starts */
    uint32_t *restored;   /* on --resume: samples per row restored */
    uint32_t rows_restored;
    uint64_t samples_restored; /* sum over rows */
    rt_progress progress;
    rt_farm_rank0 own;    /* the framebuffer and hooks the farm gets */
    rt_farm_client client; /* the hooks' context */
    struct rt_run_writer *writer; /* a frame job's writer thread, or NULL */
} rt_run_root;

/* What the run measures. */
typedef struct rt_run_result {
    double setup;         /* seconds from the scene broadcast to the render's start */
    rt_farm_result farm;
} rt_run_result;

/* The whole run, as main holds it. */
typedef struct rt_run {
    rt_run_cmd cmd;
    rt_run_rank rank;
    rt_run_setup setup;
    rt_run_root root;
    rt_run_result result;
} rt_run;

/* checks.c: rank 0 checks the file system and the machine, every rank its
 * thread count (rank gets threads and bound); cmd gets the checkpoint's
 * default path. A non-zero exit code with err filled, or RT_EXIT_OK. */
rt_exit_code rt_run_check(rt_run_cmd *cmd, rt_run_rank *rank, char *err, size_t errlen);

/* setup.c */
/* --dump-scene: rank 0 writes the scene as JSON; an exit code. */
rt_exit_code rt_run_dump_scene(const rt_options *o);
/* Rank 0 builds (or loads) the scene and every rank receives it into s; an
 * exit code, err filled on rank 0. */
rt_exit_code rt_run_scene(const rt_options *o, const rt_run_rank *rank, rt_run_setup *s, char *err, size_t errlen);
/* Every rank: intersector, camera, camera-ray lists. Fails the job itself. */
void rt_run_renderer(const rt_options *o, const rt_run_rank *rank, rt_run_setup *s);
/* Every rank, in a frame job: r = s's renderer with frame `frame`'s camera
 * and time interval (rt_anim_frame) and its camera-ray lists (into *lists,
 * whose former lists are freed). A status: any thread may call it. */
int rt_run_frame_renderer(const rt_options *o, const rt_run_setup *s, uint32_t frame, rt_renderer *r,
                          rt_run_cam_lists *lists);

/* Every rank: the farm's job (units, threads, the farm's policy). */
void rt_run_job(const rt_options *o, const rt_run_rank *rank, rt_run_setup *s);
/* The checkpoint's identity of o's image (of frame o->frame in a frame job). */
rt_ckpt_id rt_run_ckpt_id(const rt_options *o, const rt_run_setup *s);
/* Rank 0: the framebuffer, the restored checkpoint, the progress line and
 * the hooks; prints the run's first line. Fails the job itself. */
void rt_run_root_init(const rt_options *o, const rt_run_rank *rank, const rt_run_setup *s, rt_run_root *r);
/* The hooks every run has (progress line, signal's stop), for r's client. */
rt_farm_hooks rt_run_hooks(rt_run_root *r);
/* Rank 0: the run's first line on stderr, after `what` ("" or "frames
 * ..., "). */
void rt_run_say_start(const rt_options *o, const rt_run_rank *rank, const rt_run_setup *s, const char *what);

/* ckpt.c: the checkpoint's life in a run. */
/* Rank 0: a writable path, there on --resume and not there otherwise; an
 * exit code, err filled. */
rt_exit_code rt_run_ckpt_check(const rt_options *o, char *err, size_t errlen);
/* Rank 0: the framebuffer of sums, the checkpoint's rows restored into it
 * on --resume (r->ckpt set). Fails the job itself. */
void rt_run_ckpt_framebuffer(const rt_options *o, const rt_farm *f, rt_run_root *r);
/* The farm's save hook. */
int rt_run_ckpt_save(rt_farm_client *c, const uint32_t *committed, const int64_t *acc);
/* The whole render into the checkpoint (the image could not be written). */
int rt_run_ckpt_keep_render(const rt_options *o, const rt_run_root *r);
/* The image is written: remove the checkpoint, or keep it complete. */
void rt_run_ckpt_done(const rt_options *o, const rt_run_root *r);

/* summary.c: rank 0 after the render: the image file, the checkpoint
 * (removed or kept), the summary on stdout, --stats and --trace. */
void rt_run_finish(const rt_run_cmd *cmd, const rt_run_rank *rank, const rt_run_setup *s, rt_run_root *r,
                   const rt_run_result *res);
/* What the summary says of a frame's camera-ray lists, taken before the
 * next frame rebuilds them (the writer thread prints it later). */
typedef struct rt_run_lists {
    int built;
    uint32_t tiles, listed;
    size_t cand, bytes;
} rt_run_lists;
rt_run_lists rt_run_lists_of(const rt_run_setup *s);
/* A failure kept for the main thread (only it calls MPI). */
typedef struct rt_run_fault {
    rt_exit_code code;
    char msg[1024];
} rt_run_fault;
/* How rank 0 finishes a frame. */
typedef struct rt_run_finish_how {
    rt_run_lists lists;
    rt_run_fault *fault;  /* NULL: a failure ends the job at once */
    int ckpt;             /* this frame may write or remove the checkpoint */
    uint32_t frames_peak; /* frames held on rank 0 at most so far (0: one image) */
    uint64_t *hash;       /* when not NULL: gets the image hash */
} rt_run_finish_how;
/* rt_run_finish without the progress line's end, in any thread when
 * how->fault is given (s read-only, its camera-ray lists from how): 0, or
 * -1 with how->fault filled. Reads r, never frees it. */
int rt_run_finish_frame(const rt_run_cmd *cmd, const rt_run_rank *rank, const rt_run_setup *s, const rt_run_root *r,
                        const rt_run_result *res, const rt_run_finish_how *how);
/* The three values at `first` of every pixel of acc (the colour 0, or an
 * AOV of lay) as 3 sums per pixel of the job's samples (rt_image_extract);
 * NULL when out of memory. Free with rt_mem_free. */
int64_t *rt_run_values(const rt_job *j, rt_layout lay, const int64_t *acc, uint32_t first);

/* A frame job's end on rank 0: the whole range's totals on stdout (the
 * farm's result of the range, frames rendered and skipped, the peak of
 * frames held). */
void rt_run_range_summary(const rt_run_cmd *cmd, const rt_run_rank *rank, const rt_farm_result *res,
                          uint32_t rendered, uint32_t skipped, uint32_t frames_peak);
/* --done-file: one line, written atomically (a warning when it cannot be). */
void rt_run_write_done(const char *path, uint64_t hash, int lost, const char *output);

/* sequence.c: a frame job (--frames, --frame): the frames of the range
 * still to render as one schedule over the same scene, intersector and
 * farm (units across frames, at most RT_POLICY_FRAMES_IN_FLIGHT frames in
 * flight), each handed to rank 0's writer thread as soon as its last sums
 * are in; on --resume, frames whose files exist are skipped and the
 * checkpoint's frames in flight continue. */
void rt_run_frames(rt_run *run);

/* writer.c: a frame job's writer thread on rank 0 (rank and s outlive it;
 * s read-only, as rt_run_finish_frame). */
#define RT_RUN_WRITER_QUEUE 2 /* frames waiting for the writer at most */
/* Frames rank 0 holds at most: in flight, waiting, being written. */
#define RT_RUN_FRAMES_HELD (RT_POLICY_FRAMES_IN_FLIGHT + RT_RUN_WRITER_QUEUE + 1)
typedef struct rt_run_writer rt_run_writer;
/* Starts the thread; fails the job itself. */
rt_run_writer *rt_run_writer_start(const rt_run_rank *rank, const rt_run_setup *s);
/* A frame's framebuffer is allocated (counted in the peak). */
void rt_run_writer_hold(rt_run_writer *w);
/* Hands over frame `fo` (its files in paths, copied) and the render in
 * root and result (moved: they are zeroed); `last`: the job's last frame
 * (it may write or remove the checkpoint). Waits while the queue is full;
 * an earlier frame's failed write ends the job here. */
void rt_run_writer_put(rt_run_writer *w, const rt_run_cmd *cmd, const rt_options *fo, const rt_frame_paths *paths,
                       rt_run_root *root, rt_run_result *result, int last);
/* Waits for every queued frame to be written, then ends the thread and
 * frees w; a failed write ends the job here (one line, its exit code).
 * last_hash: the image hash of the frame handed over with `last`, peak:
 * the most frames held at once. */
void rt_run_writer_finish(rt_run_writer *w, uint64_t *last_hash, uint32_t *peak);
/* A signal stops the job: the file being written is finished, the frames
 * waiting are dropped (rendered again on --resume), w is freed. */
void rt_run_writer_stop(rt_run_writer *w);


/* Frees what a frame's render left (root, res), and zeroes them. */
void rt_run_release(rt_run_root *r, rt_run_result *res);
/* Frees what each part holds (parts never filled are zero). */
void rt_run_free(rt_run *run);

#endif
