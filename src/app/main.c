/* main.c - one run of rt-mpi, top to bottom: options -> MPI -> checks ->
 * scene (rank 0) -> broadcast -> acceleration structure -> distributed
 * render -> image file -> summary. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "accel.h"
#include "clock.h"
#include "cli.h"
#include "farm.h"
#include "hash.h"
#include "image.h"
#include "image_formats.h"
#include "image_io.h"
#include "material.h"
#include "mem.h"
#include "primary.h"
#include "progress.h"
#include "report.h"
#include "render.h"
#include "scene.h"
#include "scene_json.h"
#include "scenes.h"
#include "status.h"

#define EXIT_RUNTIME 1
#define EXIT_USAGE 2
#define EXIT_CHECKPOINT 3

/* Threads from the environment when -j is 0: OMP_NUM_THREADS if it is set
 * (it must then be a positive whole number), else the rank's cores. */
static int pick_threads(const rt_farm *f, const rt_options *o, char *err, size_t errlen)
{
    if (o->threads > 0)
        return o->threads;
    const char *env = getenv("OMP_NUM_THREADS");
    if (env && *env) {
        uint64_t v;
        if (rt_cli_parse_u64(env, 1, 4096, &v) != 0) {
            snprintf(err, errlen, "OMP_NUM_THREADS='%s' is not a whole number from 1 to 4096", env);
            return -1;
        }
        return (int)v;
    }
    return rt_farm_default_threads(f);
}

/* Refuse up front a framebuffer the machine cannot hold: rank 0 keeps 24
 * bytes of sums per pixel, 3 bytes of 8-bit output for the hash, and the
 * output format's own pixels (up to 12 bytes: float RGB). */
static int check_memory(const rt_options *o, char *err, size_t errlen)
{
    double need = (double)o->width * o->height * (3 * sizeof(int64_t) + 3 + 12);
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    double have = pages > 0 && page > 0 ? (double)pages * (double)page : 0;
    if (have > 0 && need > 0.9 * have) {
        snprintf(err, errlen,
                 "a %u x %u image needs about %.1f GiB of memory on rank 0, more than this machine has "
                 "(%.1f GiB)",
                 o->width, o->height, need / 1073741824.0, have / 1073741824.0);
        return -1;
    }
    return 0;
}

/* The command that reproduces this image: every option that changes a pixel,
 * none that only changes how the work is spread (-j, --band, ranks) or where
 * it goes (-o), so the file is byte-identical however it was rendered. */
static void repro_command(const rt_options *o, char *buf, size_t n)
{
    char scene[320], grid[32] = "", format[48] = "";
    if (o->scene_file)
        snprintf(scene, sizeof scene, "--scene-file %s", o->scene_file);
    else
        snprintf(scene, sizeof scene, "--scene %s", o->scene);
    if (!o->scene_file && !strcmp(o->scene, "final")) /* the only scene --grid shapes */
        snprintf(grid, sizeof grid, " --grid %d", o->grid);
    if (o->bit_depth != 8 || o->ppm_ascii)
        snprintf(format, sizeof format, "%s%s", o->bit_depth != 8 ? " --bit-depth 16" : "",
                 o->ppm_ascii ? " --ppm-ascii" : "");
    /* The BVH's box-test variants find the same hits, and each node may pick
     * its own (RT_ACCEL): the file names the BVH, not rank 0's variant. */
    rt_accel_kind accel = (rt_accel_kind)o->accel;
    if (accel == RT_ACCEL_BVH_SSE || accel == RT_ACCEL_BVH_SCALAR)
        accel = RT_ACCEL_BVH;
    snprintf(buf, n, "rt-mpi %s%s --width %u --height %u --samples %u --max-depth %u --seed %" PRIu64
             " --diffuse %s --accel %s%s",
             scene, grid, o->width, o->height, o->samples, o->max_depth, o->seed,
             rt_diffuse_name((rt_diffuse)o->diffuse), rt_accel_name(accel), format);
}

static void write_preview(void *arg, uint32_t pass, uint32_t samples, const uint32_t *committed, const int64_t *acc)
{
    const rt_options *o = arg;
    const char *path = o->preview ? o->preview : o->output;
    char info[64];
    snprintf(info, sizeof info, "pass %u of %u, %u of %u spp", pass, o->passes, samples, o->samples);
    rt_text text[] = {{"Software", "rt-mpi " RT_VERSION}, {"rt-mpi:preview", info}};
    /* In the format (and bit depth) its extension names, like the output. */
    rt_image_write_opts wo = {o->bit_depth, o->ppm_ascii, text, 2};
    int st = rt_image_write_rows(path, acc, o->width, o->height, committed, &wo);
    if (st)
        fprintf(stderr, "rt-mpi: warning: cannot write preview %s: %s\n", path, rt_status_str(st));
}

/* A checkpoint that holds the whole finished image (every row complete). */
static int save_finished(const rt_options *o, const rt_ckpt_job *ck, const int64_t *acc)
{
    uint32_t *all = malloc(o->height * sizeof *all);
    if (!all)
        return RT_ENOMEM;
    for (uint32_t y = 0; y < o->height; y++)
        all[y] = o->samples;
    int st = rt_ckpt_write(o->checkpoint, ck, all, acc);
    free(all);
    return st;
}

/* The scene of this run, named or from a file; an exit code. */
static int make_scene(const rt_options *o, rt_scene *s, char *err, size_t errlen)
{
    int st = o->scene_file ? rt_scene_json_load(s, o->scene_file, err, errlen)
                           : rt_scene_build_named(s, o->scene, o->seed, o->grid);
    if (st && !o->scene_file)
        snprintf(err, errlen, "building the scene: %s", rt_status_str(st));
    return !st ? 0 : st == RT_ENOMEM || !o->scene_file ? EXIT_RUNTIME : EXIT_USAGE;
}

/* --dump-scene: writes the scene a run would render, as JSON; an exit code. */
static int dump_scene(const rt_options *o)
{
    char err[1024] = "";
    rt_scene s;
    rt_scene_init(&s);
    int code = rt_cli_check_path("--dump-scene", o->dump_scene, err, sizeof err) ? EXIT_USAGE : 0;
    if (!code)
        code = make_scene(o, &s, err, sizeof err);
    if (!code) {
        int st = rt_scene_json_dump(&s, o->dump_scene);
        if (st) {
            snprintf(err, sizeof err, "writing %s: %s", o->dump_scene, rt_status_str(st));
            code = EXIT_RUNTIME;
        }
    }
    if (code)
        fprintf(stderr, "rt-mpi: error: %s\n", err);
    rt_scene_free(&s);
    return code;
}

int main(int argc, char **argv)
{
    double t_start = rt_now();
    rt_options opt;
    rt_cli_defaults(&opt);
    char err[1024] = "";
    rt_cli_action action = rt_cli_parse(argc, argv, &opt, err, sizeof err);

    rt_farm farm;
    if (rt_farm_init(&farm, &argc, &argv) != RT_OK) {
        fprintf(stderr, "rt-mpi: error: MPI initialisation failed\n");
        return EXIT_RUNTIME;
    }
    const int root = farm.rank == 0;
    if (action == RT_CLI_DUMP_SCENE) { /* rank 0 writes the scene, nothing renders */
        int code = root ? dump_scene(&opt) : 0;
        rt_farm_finalize(&farm);
        return code;
    }
    if (action == RT_CLI_HELP || action == RT_CLI_VERSION || action == RT_CLI_LIST_SCENES) {
        if (root) {
            if (action == RT_CLI_HELP)
                fputs(rt_cli_usage(), stdout);
            else if (action == RT_CLI_VERSION)
                printf("rt-mpi %s (sampling version %u)\n", RT_VERSION, RT_RENDER_SAMPLING);
            for (unsigned i = 0; action == RT_CLI_LIST_SCENES && i < rt_scenes_count(); i++)
                printf("%-10s %s\n", rt_scenes_info(i)->name, rt_scenes_info(i)->summary);
        }
        rt_farm_finalize(&farm);
        return 0;
    }

    /* Every rank parsed the same argv; rank 0 alone checks the file system
     * and the machine, then tells the others. */
    int code = action == RT_CLI_ERROR ? EXIT_USAGE : 0;
    char ckpt_default[4096];
    if (!code && !opt.no_checkpoint && !opt.checkpoint) {
        snprintf(ckpt_default, sizeof ckpt_default, "%s.ckpt", opt.output);
        opt.checkpoint = ckpt_default;
    }
    if (!code && root && rt_cli_check_output(&opt, err, sizeof err) != 0)
        code = EXIT_USAGE;
    if (!code && root && check_memory(&opt, err, sizeof err) != 0)
        code = EXIT_USAGE;
    if (!code && root && opt.checkpoint) {
        if (rt_cli_check_path("--checkpoint", opt.checkpoint, err, sizeof err) != 0) {
            code = EXIT_USAGE;
        } else if (opt.resume && access(opt.checkpoint, F_OK) != 0) {
            snprintf(err, sizeof err, "--resume: no checkpoint '%s' to resume from", opt.checkpoint);
            code = EXIT_CHECKPOINT;
        } else if (!opt.resume && access(opt.checkpoint, F_OK) == 0) {
            snprintf(err, sizeof err,
                     "checkpoint '%s' exists: pass --resume to continue that render, or delete it to start over",
                     opt.checkpoint);
            code = EXIT_CHECKPOINT;
        }
    }
    int threads = 1, bound = 0;
    if (!code) {
        threads = pick_threads(&farm, &opt, err, sizeof err);
        if (threads < 0)
            code = EXIT_USAGE;
        else
            bound = rt_farm_bind_threads(&farm, threads);
    }
#ifndef RT_HAVE_EMBREE
    if (!code && opt.accel == RT_ACCEL_EMBREE) {
        snprintf(err, sizeof err, "--accel embree: this build has no Embree (configure with -DRT_EMBREE=ON)");
        code = EXIT_USAGE;
    }
#endif
    if (!code && root && farm.omp_bound && farm.mask_share > 1)
        fprintf(stderr, "rt-mpi: warning: OMP_PROC_BIND is set and %d ranks of a node share the same CPUs: each binds "
                        "its threads from the first place on, onto the same cores (give each rank its own cores, e.g. "
                        "mpirun --map-by slot:PE=N, or unset OMP_PROC_BIND)\n", farm.mask_share);
    if (!code && root && opt.threads > farm.cores)
        fprintf(stderr, "rt-mpi: warning: -j %d is more than the %d cores available; threads will share cores\n",
                opt.threads, farm.cores);
    /* Scene: built (or read and checked) on rank 0 before anything renders,
     * so a bad scene file is bad input like a bad option. */
    rt_scene built;
    rt_scene_init(&built);
    if (!code && root)
        code = make_scene(&opt, &built, err, sizeof err);
    rt_farm_bcast_int(&farm, &code);
    if (code) {
        if (root && err[0])
            fprintf(stderr, "rt-mpi: error: %s\n", err);
        rt_scene_free(&built);
        rt_farm_finalize(&farm);
        return code;
    }

    /* The scene is broadcast as bytes and rebuilt from those bytes on every
     * rank (rank 0 included). */
    uint8_t *blob = NULL;
    size_t blob_len = 0;
    if (root) {
        int st = rt_scene_serialize(&built, &blob, &blob_len);
        if (st)
            rt_farm_fail(&farm, EXIT_RUNTIME, "encoding the scene: %s", rt_status_str(st));
        rt_scene_free(&built);
    }
    rt_farm_bcast_bytes(&farm, &blob, &blob_len);
    rt_scene scene;
    int st = rt_scene_deserialize(&scene, blob, blob_len);
    if (st)
        rt_farm_fail(&farm, EXIT_RUNTIME, "decoding the broadcast scene: %s", rt_status_str(st));
    uint64_t scene_hash = rt_hash_bytes(RT_HASH_INIT, blob, blob_len);
    free(blob);

    rt_accel *accel = NULL;
    st = rt_accel_new(&accel, &scene, (rt_accel_kind)opt.accel);
    if (st)
        rt_farm_fail(&farm, EXIT_RUNTIME, "building the %s intersector: %s", rt_accel_name(opt.accel),
                     rt_status_str(st));
    rt_render_params rp = {opt.width, opt.height, opt.samples, opt.max_depth, opt.seed, (rt_diffuse)opt.diffuse};
    rt_renderer renderer;
    st = rt_render_init(&renderer, &scene, accel, &rp);
    if (st)
        rt_farm_fail(&farm, EXIT_USAGE, "camera: %s", rt_status_str(st));
    renderer.stop = rt_farm_stop_flag();
    /* Our BVH also gets candidate lists for the camera rays (brute force and
     * Embree stay as they are: the oracle and the comparison). */
    rt_primary *primary = NULL;
    if (rt_accel_bvh(accel)) {
        st = rt_primary_build(&primary, &scene, &renderer.camera, opt.width, opt.height);
        if (st)
            rt_farm_fail(&farm, EXIT_RUNTIME, "camera-ray lists: %s", rt_status_str(st));
        renderer.primary = primary;
    }

    rt_farm_job job;
    memset(&job, 0, sizeof job);
    job.renderer = &renderer;
    job.sched.height = opt.height;
    job.sched.samples = opt.samples;
    job.sched.band = opt.band;
    job.sched.max_band = 16;
    job.sched.ranks = (uint32_t)farm.size;
    job.sched.units_per_rank = 8;
    job.sched.min_samples = 1;
    job.sched.passes = opt.passes;
    if (opt.passes > 1) {
        job.on_pass = write_preview;
        job.on_pass_ctx = &opt;
    }
    job.threads = threads;
    job.prefetch = (int)opt.prefetch;
    job.empty_units = opt.empty_units;
    job.root_serves_only = opt.serve_only;
    job.checkpoint = opt.checkpoint;
    job.checkpoint_interval = opt.checkpoint_interval;
    rt_ckpt_job ck = {opt.width, opt.height, opt.samples, opt.max_depth, (uint32_t)opt.diffuse,
                      opt.accel != RT_ACCEL_EMBREE, opt.seed, scene_hash, RT_RENDER_SAMPLING};
    job.ckpt_job = ck;
    job.trace = opt.trace != NULL;

    /* Rank 0 owns the framebuffer of sums; a resumed run starts from the
     * checkpoint's complete rows. */
    size_t npix = (size_t)opt.width * opt.height;
    uint32_t *restored = NULL;
    uint32_t rows_restored = 0;
    uint64_t samples_restored = 0; /* row-samples: sum over rows */
    if (root) {
        job.acc = rt_mem_zeroed(npix * 3 * sizeof *job.acc);
        if (!job.acc)
            rt_farm_fail(&farm, EXIT_RUNTIME, "out of memory for the %u x %u framebuffer", opt.width, opt.height);
        if (opt.resume) {
            restored = calloc(opt.height, sizeof *restored);
            if (!restored)
                rt_farm_fail(&farm, EXIT_RUNTIME, "out of memory");
            st = rt_ckpt_read(opt.checkpoint, &ck, restored, job.acc, &rows_restored, err, sizeof err);
            if (st)
                rt_farm_fail(&farm, EXIT_CHECKPOINT, "--resume: cannot use checkpoint '%s': %s", opt.checkpoint,
                             err[0] ? err : rt_status_str(st));
            job.committed = restored;
            for (uint32_t y = 0; y < opt.height; y++)
                samples_restored += restored[y];
        }
    }
    rt_progress progress;
    rt_progress_init(&progress, opt.height, opt.quiet || !root);
    progress.base_rows = rows_restored;
    progress.passes = (int)opt.passes;
    progress.pass = 1;
    job.progress = root ? &progress : NULL;
    if (root && !opt.quiet) {
        fprintf(stderr, "rt-mpi: %ux%u, %u spp, depth %u, seed %" PRIu64 ", %u spheres, %d rank%s x %d thread%s\n",
                opt.width, opt.height, opt.samples, opt.max_depth, opt.seed, scene.n_spheres, farm.size,
                farm.size > 1 ? "s" : "", threads, threads > 1 ? "s" : "");
        if (opt.resume)
            fprintf(stderr, "rt-mpi: resuming from %s: %.1f%% of the samples already done\n", opt.checkpoint,
                    100.0 * (double)samples_restored / ((double)opt.height * opt.samples));
    }

    rt_farm_result res;
    rt_farm_render(&farm, &job, &res);

    if (root) {
        rt_progress_finish(&progress, res.segments);
        uint8_t *rgb = malloc(npix * 3);
        if (!rgb)
            rt_farm_fail(&farm, EXIT_RUNTIME, "out of memory for the output image");
        rt_image_to_rgb8(job.acc, npix, opt.samples, rgb);
        uint64_t hash = rt_image_hash(rgb, npix * 3);
        char seed_s[32], spp_s[32], sampling_s[16], cmdline[512];
        snprintf(seed_s, sizeof seed_s, "%" PRIu64, opt.seed);
        snprintf(sampling_s, sizeof sampling_s, "%u", RT_RENDER_SAMPLING);
        snprintf(spp_s, sizeof spp_s, "%u", opt.samples);
        repro_command(&opt, cmdline, sizeof cmdline);
        rt_text text[] = {
            {"Software", "rt-mpi " RT_VERSION},
            {"rt-mpi:seed", seed_s},
            {"rt-mpi:samples", spp_s},
            {"rt-mpi:command", cmdline},
            /* Which random numbers the samples drew: the command reproduces
             * this image only with a build of the same sampling version. */
            {"rt-mpi:sampling", sampling_s},
        };
        rt_image_write_opts wo = {opt.bit_depth, opt.ppm_ascii, text, (int)(sizeof text / sizeof text[0])};
        st = rt_image_write(opt.output, job.acc, opt.width, opt.height, opt.samples, &wo);
        if (st) {
            /* Keep the finished work: a resume only has to write the image. */
            const char *saved = "";
            if (opt.checkpoint && save_finished(&opt, &ck, job.acc) == RT_OK)
                saved = " (the rendered image is saved in the checkpoint: free space and rerun with --resume)";
            rt_farm_fail(&farm, EXIT_RUNTIME, "writing %s: %s%s", opt.output, rt_status_str(st), saved);
        }
        if (opt.checkpoint && !opt.keep_checkpoint)
            unlink(opt.checkpoint);
        else if (opt.checkpoint && (st = save_finished(&opt, &ck, job.acc)) != RT_OK)
            fprintf(stderr, "rt-mpi: warning: cannot write checkpoint %s: %s\n", opt.checkpoint, rt_status_str(st));
        double rss_min = res.ranks[0].maxrss_mb, rss_max = rss_min;
        for (int i = 1; i < farm.size; i++) {
            if (res.ranks[i].maxrss_mb < rss_min)
                rss_min = res.ranks[i].maxrss_mb;
            if (res.ranks[i].maxrss_mb > rss_max)
                rss_max = res.ranks[i].maxrss_mb;
        }
        printf("output:        %s\n", opt.output);
        printf("image:         %ux%u, %u spp, max depth %u, seed %" PRIu64 "\n", opt.width, opt.height,
               opt.samples, opt.max_depth, opt.seed);
        if (opt.scene_file)
            printf("scene:         file %s, %u spheres, hash %016" PRIx64 "\n", opt.scene_file, scene.n_spheres,
                   scene_hash);
        else if (!strcmp(opt.scene, "final"))
            printf("scene:         final, grid %d, %u spheres, hash %016" PRIx64 "\n", opt.grid, scene.n_spheres,
                   scene_hash);
        else
            printf("scene:         %s, %u spheres, hash %016" PRIx64 "\n", opt.scene, scene.n_spheres, scene_hash);
        const char *box_test = rt_accel_box_test(accel);
        printf("intersector:   %s (%s%s", rt_accel_name(opt.accel), box_test ? box_test : "",
               box_test ? " box test, " : "");
        if (renderer.bvh_avx)
            printf("packets of %d rays, ", RT_RENDER_PACKET);
        if (primary) {
            uint32_t tiles, listed;
            size_t cand;
            rt_primary_stats(primary, &tiles, &listed, &cand);
            printf("camera-ray lists on %u of %u tiles, ", listed, tiles);
        }
        printf("%.0f KiB)\n", (rt_accel_bytes(accel) + rt_primary_bytes(primary)) / 1024.0);
        printf("ranks:         %d x %d threads%s, %u units", farm.size, threads, bound ? " (one per CPU, bound)" : "",
               res.units);
        if (samples_restored)
            printf(", %.1f%% of the samples restored from %s (%u complete rows)",
                   100.0 * (double)samples_restored / ((double)opt.height * opt.samples), opt.checkpoint, rows_restored);
        printf("\n");
        printf("wall time:     %.3f s render, %.3f s total\n", res.wall, rt_now() - t_start);
        printf("ray segments:  %" PRIu64 " (%.3f M/s)\n", res.segments,
               res.wall > 0 ? (double)res.segments / res.wall / 1e6 : 0.0);
        printf("peak memory:   %.1f MB on rank 0, %.1f to %.1f MB per rank\n", res.ranks[0].maxrss_mb, rss_min,
               rss_max);
        for (int i = 0; i < farm.size && farm.size > 1; i++)
            printf("rank %d: %.0f units, %.1f rows, %.3f s busy, %.3f s waiting, %.3f s communicating, "
                   "%.3f M segments/s\n",
                   i, res.ranks[i].units, res.ranks[i].rows, res.ranks[i].busy, res.ranks[i].wait, res.ranks[i].comm,
                   res.ranks[i].busy > 0 ? res.ranks[i].segments / res.ranks[i].busy / 1e6 : 0.0);
        printf("image hash:    %016" PRIx64 "\n", hash);
        fflush(stdout);
        rt_run_summary sum = {opt.width, opt.height, opt.samples, opt.max_depth, opt.seed, scene_hash, hash,
                              opt.output, rt_accel_name(opt.accel), farm.size, threads, farm.mpi, res.units,
                              rows_restored, res.wall, rt_now() - t_start, res.segments, res.ranks};
        if (opt.stats && (st = rt_report_stats(opt.stats, &sum)) != RT_OK)
            fprintf(stderr, "rt-mpi: warning: cannot write %s: %s\n", opt.stats, rt_status_str(st));
        if (opt.trace && (st = rt_report_trace(opt.trace, res.trace, res.n_trace, farm.size)) != RT_OK)
            fprintf(stderr, "rt-mpi: warning: cannot write %s: %s\n", opt.trace, rt_status_str(st));
        free(rgb);
        rt_mem_free(job.acc, npix * 3 * sizeof *job.acc);
        free(restored);
        free(res.ranks);
        free(res.trace);
    }
    rt_primary_free(primary);
    rt_accel_free(accel);
    rt_scene_free(&scene);
    rt_farm_finalize(&farm);
    return 0;
}
