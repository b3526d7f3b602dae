/* setup.c - from checked options to a job the farm can run: the scene
 * (built or loaded on rank 0, broadcast as bytes), the renderer every rank
 * builds from those bytes, and the farm's job with its framebuffer, the
 * restored checkpoint and the hooks (progress, previews, checkpoints). */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image_write.h"
#include "mem.h"
#include "policy.h"
#include "rt_config.h"
#include "run.h"
#include "scene_json.h"
#include "scenes.h"
#include "status.h"
#include "texture_image.h"

/* The earth texture of the named scenes that show it, read from
 * --texture-dir (its file listed in *files); an exit code (bad input:
 * RT_EXIT_USAGE) with err set. */
static rt_exit_code read_earth(const rt_options *o, rt_texture_image *img, rt_scene_files *files, char *err, size_t errlen)
{
    const char *dir = o->texture_dir ? o->texture_dir : ".";
    char path[4096];
    if (snprintf(path, sizeof path, "%s/earthmap.jpg", dir) >= (int)sizeof path) {
        snprintf(err, errlen, "--texture-dir: path too long");
        return RT_EXIT_USAGE;
    }
    int st = rt_texture_image_load(path, NULL, img);
    if (st == RT_ENOFILE)
        snprintf(err, errlen,
                 "%s: no such file: scene '%s' needs the book's earth texture (images/earthmap.jpg of the book's "
                 "repository, RayTracing/raytracing.github.io); give its directory with --texture-dir",
                 path, o->scene);
    else if (st)
        snprintf(err, errlen, "%s: %s", path, rt_status_str(st));
    if (!st && (st = rt_scene_files_add(files, path)) != RT_OK)
        snprintf(err, errlen, "%s", rt_status_str(st));
    return !st ? RT_EXIT_OK : st == RT_ENOMEM ? RT_EXIT_RUNTIME : RT_EXIT_USAGE;
}

/* The scene of this run, named or from a file, and the files of its
 * images; an exit code. */
static rt_exit_code make_scene(const rt_options *o, rt_scene *s, rt_scene_files *files, char *err, size_t errlen)
{
    if (o->scene_file) {
        int st = rt_scene_json_load(s, o->scene_file, files, err, errlen);
        return !st ? RT_EXIT_OK : st == RT_ENOMEM ? RT_EXIT_RUNTIME : RT_EXIT_USAGE;
    }
    const rt_scene_info *info = rt_scenes_find(o->scene);
    rt_texture_image earth = {0, 0, NULL};
    if (info && info->needs_earth) {
        rt_exit_code code = read_earth(o, &earth, files, err, errlen);
        if (code)
            return code;
    }
    const rt_scene_image img = {earth.width, earth.height, earth.texels};
    int st = rt_scene_build_named(s, o->scene, o->job.seed, o->grid, &img);
    rt_texture_image_free(&earth);
    if (st)
        snprintf(err, errlen, "building the scene: %s", rt_status_str(st));
    return st ? RT_EXIT_RUNTIME : RT_EXIT_OK;
}

rt_exit_code rt_run_dump_scene(const rt_options *o)
{
    char err[1024] = "";
    rt_scene s;
    rt_scene_files files = {NULL, 0, 0};
    rt_scene_init(&s);
    rt_exit_code code = rt_cli_check_path("--dump-scene", o->dump_scene, err, sizeof err) ? RT_EXIT_USAGE : RT_EXIT_OK;
    if (!code)
        code = make_scene(o, &s, &files, err, sizeof err);
    if (!code) {
        int st = rt_scene_json_dump(&s, &files, o->dump_scene);
        if (st) {
            snprintf(err, sizeof err, "writing %s: %s", o->dump_scene, rt_status_str(st));
            code = RT_EXIT_RUNTIME;
        }
    }
    if (code)
        fprintf(stderr, "rt-mpi: error: %s\n", err);
    rt_scene_files_free(&files);
    rt_scene_free(&s);
    return code;
}

rt_exit_code rt_run_scene(const rt_options *o, const rt_run_rank *rank, rt_run_setup *s, char *err, size_t errlen)
{
    /* Built (or read and checked) on rank 0 before anything renders, so a
     * bad scene file is bad input like a bad option. */
    rt_scene built;
    rt_scene_init(&built);
    rt_scene_files files = {NULL, 0, 0};
    int code = rank->root ? (int)make_scene(o, &built, &files, err, errlen) : RT_EXIT_OK; /* an int to broadcast */
    if (!code && rank->root && o->anim.turn_frames && rt_anim_camera_animates(&built)) {
        snprintf(err, errlen, "--turntable: scene file '%s' animates its camera already", o->scene_file);
        code = RT_EXIT_USAGE;
    }
    rt_scene_files_free(&files);
    rt_farm_bcast_int(&rank->farm, &code);
    if (code) {
        rt_scene_free(&built);
        return (rt_exit_code)code;
    }
    /* Broadcast as bytes and rebuilt from those bytes on every rank, rank 0
     * included: every rank renders the very same scene. */
    uint8_t *blob = NULL;
    size_t len = 0;
    if (rank->root) {
        int st = rt_scene_serialize(&built, &blob, &len);
        if (st)
            rt_farm_fail(&rank->farm, RT_EXIT_RUNTIME, "encoding the scene: %s", rt_status_str(st));
        rt_scene_free(&built);
    }
    rt_farm_bcast_bytes(&rank->farm, &blob, &len);
    int st = rank->root ? rt_scene_deserialize_own(&s->scene, blob, len) : rt_scene_deserialize(&s->scene, blob, len);
    if (st)
        rt_farm_fail(&rank->farm, RT_EXIT_RUNTIME, "decoding the broadcast scene: %s", rt_status_str(st));
    s->scene_hash = rt_scene_bytes_hash(blob, len); /* the bytes' FNV-1a, from their checked checksum */
    free(blob);
    return RT_EXIT_OK;
}

static void lists(const rt_options *o, const rt_farm *f, rt_run_setup *s);

void rt_run_renderer(const rt_options *o, const rt_run_rank *rank, rt_run_setup *s)
{
    const rt_farm *f = &rank->farm;
    /* The first frame's camera and shutter (frame 0 for a single image); the
     * intersector holds the moving spheres over every frame's time. */
    const uint32_t first = o->frame_job ? o->frames.first : 0, last = o->frame_job ? o->frames.last : 0;
    rt_camera_desc cam;
    double t0, t1, lo, hi;
    int st = rt_anim_frame(&s->scene, &o->anim, first, &cam, &t0, &t1);
    if (!st)
        st = rt_anim_span(&s->scene, &o->anim, first, last, &lo, &hi);
    if (st)
        rt_farm_fail(f, RT_EXIT_USAGE, "frame %u's camera: %s", first, rt_status_str(st));
    st = rt_accel_new_span(&s->accel, &s->scene, (rt_accel_kind)o->accel, lo, hi);
    if (st)
        rt_farm_fail(f, RT_EXIT_RUNTIME, "building the %s intersector: %s", rt_accel_name(o->accel),
                     rt_status_str(st));
    st = rt_render_init(&s->renderer, &s->scene, s->accel, &o->job);
    if (!st)
        st = rt_render_frame(&s->renderer, &cam, t0, t1);
    if (st)
        rt_farm_fail(f, RT_EXIT_USAGE, "camera: %s", rt_status_str(st));
    s->renderer.stop = rt_farm_stop_flag();
    /* Our BVH also gets candidate lists for the camera rays (brute force and
     * Embree stay as they are: the oracle and the comparison). */
    if (!o->frame_job)
        lists(o, f, s);
}

/* Our BVH's camera-ray lists for renderer r's camera: book 1's over the
 * spheres, or the book-2 loop's over its world (brute force and Embree stay
 * as they are: the oracle and the comparison). A status. */
static int build_lists(const rt_options *o, const rt_run_setup *s, rt_renderer *r, rt_run_cam_lists *l)
{
    rt_run_cam_lists_free(l);
    r->primary = NULL;
    r->wlists = NULL;
    int st = RT_OK;
    if (r->world && o->accel != RT_ACCEL_BRUTE) { /* brute force stays the oracle */
        st = rt_world_lists_build(&l->world, r->world, &r->camera, s->scene.camera.pixels == RT_PIXELS_BOOK2,
                                  o->job.width, o->job.height);
        r->wlists = l->world;
    } else if (!r->world && rt_accel_bvh(s->accel)) {
        st = rt_primary_build(&l->primary, &s->scene, &r->camera, o->job.width, o->job.height);
        r->primary = l->primary;
    }
    return st;
}

static void lists(const rt_options *o, const rt_farm *f, rt_run_setup *s)
{
    const int st = build_lists(o, s, &s->renderer, &s->lists);
    if (st)
        rt_farm_fail(f, RT_EXIT_RUNTIME, "camera-ray lists: %s", rt_status_str(st));
}

int rt_run_frame_renderer(const rt_options *o, const rt_run_setup *s, uint32_t frame, rt_renderer *r,
                          rt_run_cam_lists *lists)
{
    *r = s->renderer; /* scene, intersector, job, stop flag: the job's */
    rt_run_cam_lists_free(lists);
    r->primary = NULL;
    r->wlists = NULL;
    rt_camera_desc cam;
    double t0, t1;
    int st = rt_anim_frame(&s->scene, &o->anim, frame, &cam, &t0, &t1);
    if (!st)
        st = rt_render_frame(r, &cam, t0, t1);
    if (!st) /* this frame's camera's lists, as lists() */
        st = build_lists(o, s, r, lists);
    return st;
}

/* ---- hooks: what rank 0 does while the sums come in ---------------------- */

static void on_progress(rt_farm_client *c, uint32_t pass, uint64_t rows_done, uint64_t segments)
{
    c->root->progress.pass = (int)pass;
    rt_progress_update(&c->root->progress, rows_done, segments);
}

/* After each progressive pass: the preview, in the format (and bit depth)
 * its extension names, like the output. */
static void on_pass(rt_farm_client *c, uint32_t pass, uint32_t samples, const uint32_t *committed,
                    const int64_t *acc)
{
    const rt_options *o = c->opt;
    const char *path = o->preview ? o->preview : o->output;
    char info[64];
    snprintf(info, sizeof info, "pass %u of %u, %u of %u spp", pass, o->passes, samples, o->job.samples);
    rt_text text[] = {{"Software", "rt-mpi " RT_VERSION}, {"rt-mpi:preview", info}};
    rt_image_write_opts wo = {.bit_depth = o->bit_depth, .ppm_ascii = o->ppm_ascii, .text = text, .n_text = 2};
    const size_t n = (size_t)o->job.width * o->job.height * 3;
    int64_t *colour = (int64_t *)acc;
    if (c->lay.ch != 3 && !(colour = rt_run_values(&o->job, c->lay, acc, 0))) {
        fprintf(stderr, "rt-mpi: warning: no memory for preview %s\n", path);
        return;
    }
    /* with adaptive sampling each pixel's sums come scaled to -s samples
     * (rt_image_extract): a row with samples shows them as -s */
    uint32_t *rows = NULL;
    if (c->lay.count && (rows = malloc(o->job.height * sizeof *rows)))
        for (uint32_t y = 0; y < o->job.height; y++)
            rows[y] = committed[y] ? o->job.samples : 0;
    int st = rows || !c->lay.count ? rt_image_write_rows(path, colour, o->job.width, o->job.height,
                                                         rows ? rows : committed, &wo)
                                   : RT_ENOMEM;
    free(rows);
    if (colour != acc)
        rt_mem_free(colour, n * sizeof *colour);
    if (st)
        fprintf(stderr, "rt-mpi: warning: cannot write preview %s: %s\n", path, rt_status_str(st));
}

static void on_stopped(rt_farm_client *c, int sig, int saved, uint32_t rows_done, uint32_t rows)
{
    const rt_progress *p = &c->root->progress;
    if (c->root->writer) /* the file being written is finished first */
        rt_run_writer_stop(c->root->writer);
    if (p->enabled && p->tty)
        fputc('\n', stderr);
    if (c->opt->checkpoint)
        fprintf(stderr, "rt-mpi: interrupted by signal %d: checkpoint %s %s %u of %u rows; rerun with --resume\n",
                sig, c->opt->checkpoint, saved ? "holds" : "(not updated: see the warning above) was to hold",
                rows_done, rows);
    else
        fprintf(stderr, "rt-mpi: interrupted by signal %d (no checkpoint file)\n", sig);
    fflush(stderr);
}

/* ---- the job ----------------------------------------------------------- */

void rt_run_job(const rt_options *o, const rt_run_rank *rank, rt_run_setup *s)
{
    s->job = (rt_farm_job){.renderer = &s->renderer,
                           .sched = {.band = o->band,
                                     .max_band = RT_POLICY_MAX_BAND,
                                     .ranks = (uint32_t)rank->farm.size,
                                     .units_per_rank = RT_POLICY_UNITS_PER_RANK,
                                     .min_samples = 1,
                                     .passes = o->passes,
                                     .split = o->split},
                           .threads = rank->threads,
                           .prefetch = (int)o->prefetch,
                           .empty_units = o->empty_units,
                           .root_serves_only = o->serve_only,
                           .flush_interval = o->flush_interval,
                           .flush_bytes = (size_t)o->flush_mb << 20,
                           .lease = o->lease};
}

rt_ckpt_id rt_run_ckpt_id(const rt_options *o, const rt_run_setup *s)
{
    return (rt_ckpt_id){.job = o->job,
                        .exact = o->accel != RT_ACCEL_EMBREE,
                        .scene_hash = s->scene_hash,
                        .sampling = RT_RENDER_SAMPLING,
                        .frame_job = (uint32_t)o->frame_job,
                        .first = o->frames.first,
                        .last = o->frames.last,
                        .step = o->frames.step,
                        .frame = o->frame,
                        .turn_frames = o->anim.turn_frames,
                        .turn_degrees = o->anim.turn_degrees};
}

rt_farm_hooks rt_run_hooks(rt_run_root *r)
{
    return (rt_farm_hooks){.client = &r->client, .progress = on_progress, .stopped = on_stopped};
}

void rt_run_root_init(const rt_options *o, const rt_run_rank *rank, const rt_run_setup *s, rt_run_root *r)
{
    r->ckpt = rt_run_ckpt_id(o, s);
    rt_run_ckpt_framebuffer(o, &rank->farm, r);
    rt_progress_init(&r->progress, o->job.height, o->quiet);
    r->progress.base_rows = r->rows_restored;
    r->progress.passes = (int)o->passes;
    r->progress.pass = 1;
    r->client = (rt_farm_client){.opt = o, .lay = s->renderer.lay, .root = r};
    r->own = (rt_farm_rank0){.acc = r->acc, .committed = r->restored, .trace = o->trace != NULL, .hooks = rt_run_hooks(r)};
    if (o->passes > 1)
        r->own.hooks.pass = on_pass;
    if (o->checkpoint) {
        r->own.hooks.save = rt_run_ckpt_save;
        r->own.hooks.save_interval = o->checkpoint_interval;
    }
    if (o->quiet)
        return;
    rt_run_say_start(o, rank, s, "");
    if (o->resume)
        fprintf(stderr, "rt-mpi: resuming from %s: %.1f%% of the samples already done\n", o->checkpoint,
                100.0 * (double)r->samples_restored / ((double)o->job.height * o->job.samples));
}

void rt_run_say_start(const rt_options *o, const rt_run_rank *rank, const rt_run_setup *s, const char *fr)
{
    const int ranks = rank->farm.size, threads = rank->threads;
    fprintf(stderr, "rt-mpi: %s%ux%u, %u spp, depth %u, seed %" PRIu64 ", %u spheres, %d rank%s x %d thread%s\n",
            fr, o->job.width, o->job.height, o->job.samples, o->job.max_depth, o->job.seed, s->scene.n_spheres, ranks,
            ranks > 1 ? "s" : "", threads, threads > 1 ? "s" : "");
}
