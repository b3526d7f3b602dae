/* summary.c - rank 0 after the render: the image file (with what made it in
 * its text chunks), the checkpoint removed or kept, the summary on stdout
 * (greppable in batch logs) and the --stats and --trace reports. */
#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clock.h"
#include "fileio.h"
#include "image.h"
#include "image_write.h"
#include "mem.h"
#include "report.h"
#include "rt_config.h"
#include "run.h"
#include "status.h"
#include "sysinfo.h"

/* The command that reproduces this image: every option that changes a pixel,
 * none that only changes how the work is spread (-j, --band, ranks) or where
 * it goes (-o), so the file is byte-identical however it was rendered. */
static void repro_command(const rt_options *o, char *buf, size_t n)
{
    char scene[320], grid[32] = "", format[48] = "", adapt[48] = "", frame[96] = "";
    /* the roulette only when it is not the sampler's default */
    const char *roulette = o->job.roulette == (o->job.sampler == RT_SAMPLER_SOBOL) ? ""
                           : o->job.roulette                                      ? " --roulette"
                                                                                  : " --no-roulette";
    /* Our BVH's variants find the very same hits: the file names the BVH,
     * not the box test of rank 0's node (RT_ACCEL), so the same job on
     * another mix of hosts writes the same bytes. */
    rt_accel_kind accel = (rt_accel_kind)o->accel;
    if (accel == RT_ACCEL_BVH_SSE || accel == RT_ACCEL_BVH_SCALAR)
        accel = RT_ACCEL_BVH;
    if (o->scene_file)
        snprintf(scene, sizeof scene, "--scene-file %s", o->scene_file);
    else
        snprintf(scene, sizeof scene, "--scene %s", o->scene);
    if (!o->scene_file && !strcmp(o->scene, "final")) /* the only scene --grid shapes */
        snprintf(grid, sizeof grid, " --grid %d", o->grid);
    if (o->bit_depth != 8 || o->ppm_ascii)
        snprintf(format, sizeof format, "%s%s", o->bit_depth != 8 ? " --bit-depth 16" : "",
                 o->ppm_ascii ? " --ppm-ascii" : "");
    if (o->job.noise_threshold > 0.0) /* %.17g: the very double, which decides where pixels stop */
        snprintf(adapt, sizeof adapt, " --noise-threshold %.17g", o->job.noise_threshold);
    if (o->frame_job && o->anim.turn_frames) /* %.17g: the very double the orbit turns by */
        snprintf(frame, sizeof frame, " --frame %u --turntable %.17g:%u", o->frame, o->anim.turn_degrees,
                 o->anim.turn_frames);
    else if (o->frame_job)
        snprintf(frame, sizeof frame, " --frame %u", o->frame);
    snprintf(buf, n, "rt-mpi %s%s --width %u --height %u --samples %u --max-depth %u --seed %" PRIu64
             " --diffuse %s --sampler %s%s%s%s --accel %s%s%s",
             scene, grid, o->job.width, o->job.height, o->job.samples, o->job.max_depth, o->job.seed,
             rt_diffuse_name(o->job.diffuse), rt_sampler_name(o->job.sampler), roulette,
             o->job.light == RT_LIGHT_BRUTE ? " --no-light-sampling" : "", adapt, rt_accel_name(accel),
             format, frame);
}

/* The parts of the run that the steps after the render read. */
typedef struct finish {
    const rt_run_cmd *cmd;
    const rt_options *o;
    const rt_farm *f;
    const rt_run_rank *rank;
    const rt_run_setup *s;
    const rt_run_root *r;
    const rt_farm_result *res;
    double setup; /* seconds (rt_run_result) */
    const rt_run_finish_how *how;
} finish;

/* A failure: the job ends here, or (the writer thread, which may not call
 * MPI) it is kept for the main thread and -1 returned. */
__attribute__((format(printf, 3, 4))) static int fail(const finish *F, rt_exit_code code, const char *fmt, ...)
{
    char msg[sizeof F->how->fault->msg];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (!F->how->fault)
        rt_farm_fail(F->f, code, "%s", msg);
    F->how->fault->code = code;
    memcpy(F->how->fault->msg, msg, sizeof msg);
    return -1;
}

/* Writing an output failed: the sums go to the checkpoint (when this
 * frame may write it). */
static int fail_write(const finish *F, const char *path, int st)
{
    const int kept = F->how->ckpt && rt_run_ckpt_keep_render(F->o, F->r) == RT_OK;
    return fail(F, RT_EXIT_RUNTIME, "writing %s: %s%s", path, rt_status_str(st),
                kept ? " (the rendered image is saved in the checkpoint: free space and rerun with --resume)" : "");
}

/* The output file, with what made it (PNG text chunks, EXR attributes): no
 * time, host or rank count, so that it stays byte-identical however it was
 * rendered. On failure the finished sums go to the checkpoint, so that a
 * resume only has to write the image. */
static int write_image(const finish *F, const int64_t *colour)
{
    const rt_options *o = F->o;
    char seed_s[32], spp_s[32], sampling_s[16], cmdline[640], frame_s[16];
    snprintf(seed_s, sizeof seed_s, "%" PRIu64, o->job.seed);
    snprintf(frame_s, sizeof frame_s, "%u", o->frame);
    snprintf(sampling_s, sizeof sampling_s, "%u", RT_RENDER_SAMPLING);
    snprintf(spp_s, sizeof spp_s, "%u", o->job.samples);
    repro_command(o, cmdline, sizeof cmdline);
    rt_text text[] = {
        {"Software", "rt-mpi " RT_VERSION},
        {"rt-mpi:seed", seed_s},
        {"rt-mpi:samples", spp_s},
        {"rt-mpi:command", cmdline},
        /* Which random numbers the samples drew: the command reproduces
         * this image only with a build of the same sampling version. */
        {"rt-mpi:sampling", sampling_s},
        {"rt-mpi:frame", frame_s}, /* last: only a frame job's files have it */
    };
    rt_image_write_opts wo = {.bit_depth = o->bit_depth,
                              .ppm_ascii = o->ppm_ascii,
                              .text = text,
                              .n_text = (int)(sizeof text / sizeof text[0]) - !o->frame_job};
    int st = rt_image_write(o->output, colour, o->job.width, o->job.height, o->job.samples, &wo);
    return st ? fail_write(F, o->output, st) : 0;
}

int64_t *rt_run_values(const rt_job *j, rt_layout lay, const int64_t *acc, uint32_t first)
{
    const size_t npix = (size_t)j->width * j->height;
    int64_t *out = rt_mem_zeroed(npix * 3 * sizeof *out);
    if (out)
        rt_image_extract(acc, npix, lay, first, j->samples, out);
    return out;
}

/* OUTPUT.<name>.pfm, or .exr beside an .exr output. */
static void aov_path(const char *output, const char *name, char *buf, size_t n)
{
    const char *slash = strrchr(output, '/'), *dot = strrchr(output, '.');
    size_t stem = dot && (!slash || dot > slash) ? (size_t)(dot - output) : strlen(output);
    const char *ext = rt_image_format_from_path(output) == RT_FORMAT_EXR ? "exr" : "pfm";
    snprintf(buf, n, "%.*s.%s.%s", (int)stem, output, name, ext);
}

/* The denoiser's buffers (--aov) and the samples-per-pixel map. */
static int write_extras(const finish *F)
{
    const rt_options *o = F->o;
    const rt_layout *lay = &F->s->renderer.lay;
    const int64_t *acc = F->r->acc;
    const struct {
        uint32_t first;
        const char *name;
    } aovs[] = {{lay->albedo, "albedo"}, {lay->normal, "normal"}};
    rt_text text[] = {{"Software", "rt-mpi " RT_VERSION}};
    rt_image_write_opts wo = {.bit_depth = 8, .text = text, .n_text = 1};
    for (size_t k = 0; k < sizeof aovs / sizeof aovs[0]; k++) {
        if (!aovs[k].first)
            continue;
        char path[4096];
        aov_path(o->output, aovs[k].name, path, sizeof path);
        int64_t *v = rt_run_values(&o->job, *lay, acc, aovs[k].first);
        if (!v)
            return fail(F, RT_EXIT_RUNTIME, "out of memory for the %s buffer", aovs[k].name);
        int st = rt_image_write(path, v, o->job.width, o->job.height, o->job.samples, &wo);
        rt_mem_free(v, (size_t)o->job.width * o->job.height * 3 * sizeof *v);
        if (st)
            return fail_write(F, path, st);
    }
    if (o->spp_map) {
        /* a pixel's samples as its value: count / samples once divided */
        const size_t npix = (size_t)o->job.width * o->job.height;
        int64_t *v = rt_mem_zeroed(npix * 3 * sizeof *v);
        if (!v)
            return fail(F, RT_EXIT_RUNTIME, "out of memory for the samples-per-pixel map");
        for (size_t i = 0; i < npix; i++)
            v[3 * i] = v[3 * i + 1] = v[3 * i + 2] = acc[i * lay->ch + lay->count] << RT_FIX_SHIFT;
        rt_image_write_opts wm = {.bit_depth = o->bit_depth, .ppm_ascii = o->ppm_ascii, .text = text, .n_text = 1};
        int st = rt_image_write(o->spp_map, v, o->job.width, o->job.height, o->job.samples, &wm);
        rt_mem_free(v, npix * 3 * sizeof *v);
        if (st)
            return fail_write(F, o->spp_map, st);
    }
    return 0;
}

/* Where adaptive sampling put the samples: how many pixels took
 * each count. */
static void spp_tally(rt_spp_stats *st, const int64_t *acc, size_t npix, rt_layout lay, uint32_t samples)
{
    memset(st, 0, sizeof *st);
    for (uint32_t c = RT_ADAPT_FIRST; c < samples && st->n_levels < RT_SPP_LEVELS - 1; c *= 2)
        st->count[st->n_levels++] = c;
    st->count[st->n_levels++] = samples;
    uint64_t total = 0;
    for (size_t i = 0; i < npix; i++) {
        const uint32_t n = (uint32_t)acc[i * lay.ch + lay.count];
        total += n;
        uint32_t k = 0;
        while (k + 1 < st->n_levels && st->count[k] < n)
            k++;
        st->pixels[k]++;
    }
    st->mean = npix ? (double)total / (double)npix : 0.0;
}

static void print_spp(const rt_spp_stats *st, uint32_t samples, size_t npix)
{
    printf("adaptive:      %.1f samples per pixel (%.1f%% of %u, pilots aside); pixels taking", st->mean,
           100.0 * st->mean / samples, samples);
    for (uint32_t k = 0; k < st->n_levels; k++)
        printf("%s %u: %.1f%%", k ? "," : "", st->count[k], 100.0 * (double)st->pixels[k] / (double)npix);
    printf("\n");
}

rt_run_lists rt_run_lists_of(const rt_run_setup *s)
{
    const rt_run_cam_lists *c = &s->lists;
    rt_run_lists l = {.built = c->primary || c->world,
                      .bytes = rt_primary_bytes(c->primary) + rt_world_lists_bytes(c->world)};
    if (c->primary)
        rt_primary_stats(c->primary, &l.tiles, &l.listed, &l.cand);
    if (c->world)
        rt_world_lists_stats(c->world, &l.tiles, &l.listed, &l.cand);
    return l;
}

static void print_intersector(const rt_options *o, const rt_run_setup *s, const rt_run_lists *l)
{
    const char *box_test = rt_accel_box_test(s->accel);
    printf("intersector:   %s (%s%s", rt_accel_name(o->accel), box_test ? box_test : "",
           box_test ? " box test, " : "");
    if (rt_accel_flat_quads(s->accel))
        printf("avx-512 flat test of %u quads, ", rt_accel_flat_quads(s->accel));
    if (s->renderer.bvh_avx)
        printf("packets of %d rays, ", RT_RENDER_PACKET);
    if (s->renderer.lanes)
        printf("avx-512 paths 8 a register, ");
    if (l->built)
        printf("camera-ray lists on %u of %u tiles, ", l->listed, l->tiles);
    printf("%.0f KiB)\n", (rt_accel_bytes(s->accel) + l->bytes) / 1024.0);
}

/* What every rank did: memory, rank 0's serving, lost ranks, one line a
 * rank. */
static void print_ranks(int ranks, const rt_farm_result *res)
{
    double lo = res->ranks[0].maxrss_mb, hi = lo, held = 0;
    for (int i = 1; i < ranks; i++) {
        const rt_rank_stats *r = &res->ranks[i];
        if (r->lost)
            continue;
        lo = r->maxrss_mb < lo ? r->maxrss_mb : lo;
        hi = r->maxrss_mb > hi ? r->maxrss_mb : hi;
        held = r->held_mb > held ? r->held_mb : held;
    }
    printf("peak memory:   %.1f MB on rank 0, %.1f to %.1f MB per rank", res->ranks[0].maxrss_mb, lo, hi);
    if (ranks > 1)
        printf(", at most %.1f MB of sums held by a rank", held);
    printf("\n");
    if (ranks > 1)
        printf("rank 0 served: %" PRIu64 " messages, %.1f MB in, %.3f s CPU; last sums in %.3f s after the last unit\n",
               res->msgs_in, (double)res->bytes_in / 1e6, res->serve_cpu, res->final_combine);
    if (res->lost)
        printf("lost ranks:    %d (their units were rendered again by the others)\n", res->lost);
    if (res->render_waits)
        printf("rank 0 waited: %" PRIu64 " times for units (the frames in flight), %.3f s, %.4f s CPU\n",
               res->render_waits, res->ranks[0].wait, res->render_wait_cpu);
    for (int i = 0; i < ranks && ranks > 1; i++) {
        const rt_rank_stats *r = &res->ranks[i];
        printf("rank %d: %.0f units, %.1f rows, %.3f s busy, %.3f s waiting, %.3f s communicating, "
               "%.3f M segments/s%s%s",
               i, r->units, r->rows, r->busy, r->wait, r->comm, r->busy > 0 ? r->segments / r->busy / 1e6 : 0.0,
               r->host[0] ? " on " : "", r->host);
        if (r->lost)
            printf(" (lost at %.1f s, silent for %.1f s: %u units and %.3f s of its rendering went to the others)",
                   r->lost_at, r->silent, r->units_redone, r->redone);
        printf("\n");
    }
}

static void print_summary(const finish *F, uint64_t hash, const rt_spp_stats *spp)
{
    const rt_options *o = F->o;
    const rt_job *j = &o->job;
    const rt_farm_result *res = F->res;
    const rt_run_root *r = F->r;
    const int ranks = F->f->size;
    printf("output:        %s\n", o->output);
    if (o->frame_job)
        printf("frame:         %u\n", o->frame);
    printf("image:         %ux%u, %u spp, max depth %u, seed %" PRIu64 "\n", j->width, j->height, j->samples,
           j->max_depth, j->seed);
    if (o->scene_file)
        printf("scene:         file %s", o->scene_file);
    else if (!strcmp(o->scene, "final"))
        printf("scene:         final, grid %d", o->grid);
    else
        printf("scene:         %s", o->scene);
    printf(", %u spheres, hash %016" PRIx64 "\n", F->s->scene.n_spheres, F->s->scene_hash);
    print_intersector(o, F->s, &F->how->lists);
    printf("ranks:         %d x %d threads%s, %u units", ranks, F->rank->threads,
           F->rank->bound ? " (one per CPU, bound)" : "", res->units);
    if (r->samples_restored)
        printf(", %.1f%% of the samples restored from %s (%u complete rows)",
               100.0 * (double)r->samples_restored / ((double)j->height * j->samples), o->checkpoint,
               r->rows_restored);
    printf("\n");
    if (spp)
        print_spp(spp, j->samples, (size_t)j->width * j->height);
    printf("wall time:     %.3f s render, %.3f s total\n", res->wall, rt_now() - F->cmd->t_start);
    printf("ray segments:  %" PRIu64 " (%.3f M/s)\n", res->segments,
           res->wall > 0 ? (double)res->segments / res->wall / 1e6 : 0.0);
    if (res->ranks) /* a frame of a frame job: the range's summary has them */
        print_ranks(F->f->size, res);
    if (F->how->frames_peak)
        printf("frames held:   peak %u on rank 0 (at most %u in flight, %u waiting for the writer thread, 1 being "
               "written)\n",
               F->how->frames_peak, RT_POLICY_FRAMES_IN_FLIGHT, RT_RUN_WRITER_QUEUE);
    printf("image hash:    %016" PRIx64 "\n", hash);
    fflush(stdout);
}

static void write_reports(const finish *F, uint64_t hash, const rt_spp_stats *spp)
{
    const rt_options *o = F->o;
    const rt_farm_result *res = F->res;
    char host[256];
    rt_sysinfo_hostname(host, sizeof host);
    const char *job_id = getenv("SLURM_JOB_ID");
    rt_report_origin origin = {.argc = F->cmd->argc,
                               .argv = F->cmd->argv,
                               .start = F->cmd->start,
                               .host = host,
                               .mpi_library = rt_farm_mpi_version(),
                               .slurm_job_id = job_id && *job_id ? job_id : NULL};
    rt_run_summary sum = {.job = &o->job,
                          .scene_hash = F->s->scene_hash,
                          .image_hash = hash,
                          .output = o->output,
                          .intersector = rt_accel_name(o->accel),
                          .ranks = F->f->size,
                          .threads = F->rank->threads,
                          .mpi = F->f->mpi,
                          .units = res->units,
                          .rows_restored = F->r->rows_restored,
                          .wall = res->wall,
                          .total_wall = rt_now() - F->cmd->t_start,
                          .setup = F->setup,
                          .segments = res->segments,
                          .per_rank = res->ranks,
                          .origin = origin,
                          .farm = res,
                          .spp = spp,
                          .frame_job = o->frame_job,
                          .frame = o->frame,
                          .frames_peak = F->how->frames_peak,
                          .frame_start = res->start};
    int st;
    if (o->stats && (st = rt_report_stats(o->stats, &sum)) != RT_OK)
        fprintf(stderr, "rt-mpi: warning: cannot write %s: %s\n", o->stats, rt_status_str(st));
    if (o->trace && (st = rt_report_trace(o->trace, res->trace, res->n_trace, F->f->size, &origin)) != RT_OK)
        fprintf(stderr, "rt-mpi: warning: cannot write %s: %s\n", o->trace, rt_status_str(st));
}

/* --done-file: the image is written (one line, atomically). A launcher
 * whose tasks died reports the job as failed even when the survivors
 * finished it (srun exits 137); the job script reads this instead. */
void rt_run_write_done(const char *path, uint64_t hash, int lost, const char *output)
{
    if (!path)
        return;
    rt_atomic_file f;
    int st = rt_atomic_open(&f, path);
    if (st == RT_OK) {
        fprintf(f.fp, "done %016" PRIx64 " lost %d %s\n", hash, lost, output);
        st = rt_atomic_commit(&f);
    }
    if (st)
        fprintf(stderr, "rt-mpi: warning: cannot write %s: %s\n", path, rt_status_str(st));
}

void rt_run_range_summary(const rt_run_cmd *cmd, const rt_run_rank *rank, const rt_farm_result *res,
                          uint32_t rendered, uint32_t skipped, uint32_t frames_peak)
{
    printf("range:         %u frame%s rendered, %u skipped (written before), %u units, %.3f s render, %.3f s total\n",
           rendered, rendered == 1 ? "" : "s", skipped, res->units, res->wall, rt_now() - cmd->t_start);
    printf("range segments: %" PRIu64 " (%.3f M/s)\n", res->segments,
           res->wall > 0 ? (double)res->segments / res->wall / 1e6 : 0.0);
    if (res->ranks)
        print_ranks(rank->farm.size, res);
    printf("frames held:   peak %u on rank 0 over the range (at most %u in flight, %u waiting for the writer thread, "
           "1 being written)\n",
           frames_peak, RT_POLICY_FRAMES_IN_FLIGHT, RT_RUN_WRITER_QUEUE);
    fflush(stdout);
}

int rt_run_finish_frame(const rt_run_cmd *cmd, const rt_run_rank *rank, const rt_run_setup *s, const rt_run_root *r,
                        const rt_run_result *res, const rt_run_finish_how *how)
{
    const finish F = {.cmd = cmd, .o = &cmd->opt, .f = &rank->farm, .rank = rank, .s = s, .r = r,
                      .res = &res->farm, .setup = res->setup, .how = how};
    const rt_job *j = &cmd->opt.job;
    const rt_layout lay = s->renderer.lay;
    size_t npix = (size_t)j->width * j->height;
    /* The image hash: of the 8-bit image, whatever the output format. */
    uint8_t *rgb = malloc(npix * 3);
    int64_t *colour = r->acc;
    if (!rgb || (lay.ch != 3 && !(colour = rt_run_values(j, lay, r->acc, 0)))) {
        free(rgb);
        return fail(&F, RT_EXIT_RUNTIME, "out of memory for the output image");
    }
    rt_image_to_rgb8(colour, npix, j->samples, rgb);
    uint64_t hash = rt_image_hash(rgb, npix * 3);
    free(rgb);
    const int st = write_image(&F, colour);
    if (colour != r->acc)
        rt_mem_free(colour, npix * 3 * sizeof *colour);
    if (st || write_extras(&F))
        return -1;
    if (how->ckpt)
        rt_run_ckpt_done(F.o, r);
    rt_spp_stats spp;
    if (lay.count)
        spp_tally(&spp, r->acc, npix, lay, j->samples);
    print_summary(&F, hash, lay.count ? &spp : NULL);
    write_reports(&F, hash, lay.count ? &spp : NULL);
    rt_run_write_done(F.o->done_file, hash, F.res->lost, F.o->output);
    if (how->hash)
        *how->hash = hash;
    return 0;
}

void rt_run_finish(const rt_run_cmd *cmd, const rt_run_rank *rank, const rt_run_setup *s, rt_run_root *r,
                   const rt_run_result *res)
{
    const rt_run_finish_how how = {.lists = rt_run_lists_of(s), .ckpt = 1};
    rt_progress_finish(&r->progress, res->farm.segments);
    rt_run_finish_frame(cmd, rank, s, r, res, &how);
}

void rt_run_release(rt_run_root *r, rt_run_result *res)
{
    rt_mem_free(r->acc, r->acc_len * sizeof *r->acc);
    free(r->restored);
    free(res->farm.ranks);
    free(res->farm.trace);
    memset(r, 0, sizeof *r);
    memset(res, 0, sizeof *res);
}

void rt_run_free(rt_run *run)
{
    rt_run_release(&run->root, &run->result);
    rt_run_cam_lists_free(&run->setup.lists);
    rt_accel_free(run->setup.accel);
    rt_scene_free(&run->setup.scene);
}
