/* main.c - one run of rt-mpi, top to bottom: options -> MPI -> checks ->
 * scene (rank 0, broadcast) -> renderer -> job -> distributed render ->
 * image file and summary (rank 0). Each step is a function of run.h; this
 * file is the table of contents. */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "clock.h"
#include "mem.h"
#include "report.h"
#include "rt_config.h"
#include "run.h"
#include "scenes.h"

/* --help, --version, --list-scenes: rank 0 answers, nothing renders. */
static int answer(int root, rt_cli_action action)
{
    if (!root)
        return 0;
    if (action == RT_CLI_HELP)
        fputs(rt_cli_usage(), stdout);
    if (action == RT_CLI_VERSION) {
        char features[96];
        rt_report_features(features, sizeof features, rt_farm_mpi_version());
        printf("rt-mpi %s (sampling version %u)\nfeatures: %s\nMPI library: %s\n", RT_VERSION,
               RT_RENDER_SAMPLING, features, rt_farm_mpi_version());
    }
    static const char *const BOOKS[] = {"", "Ray Tracing in One Weekend (book 1)", "Ray Tracing: The Next Week (book 2)",
                                         "Ray Tracing: The Rest of Your Life (book 3)"};
    for (unsigned i = 0; action == RT_CLI_LIST_SCENES && i < rt_scenes_count(); i++) {
        const rt_scene_info *in = rt_scenes_info(i);
        if (!i || in->book != rt_scenes_info(i - 1)->book)
            printf("%s%s:\n", i ? "\n" : "", BOOKS[in->book]);
        printf("  %-18s %s\n", in->name, in->summary);
        if (in->width)
            printf("  %-18s (the book's %u x %u, %u spp, depth %u)\n", "", in->width, in->height, in->samples,
                   in->max_depth);
    }
    return 0;
}

/* Ends the run early with code, rank 0 printing err. */
static int stop(rt_run *run, int code, const char *err)
{
    if (run->rank.root && err[0])
        fprintf(stderr, "rt-mpi: error: %s\n", err);
    rt_run_free(run);
    rt_farm_finalize(&run->rank.farm);
    return code;
}

int main(int argc, char **argv)
{
    rt_mem_keep_freed();
    rt_run run;
    memset(&run, 0, sizeof run);
    rt_run_cmd *cmd = &run.cmd;
    rt_run_rank *rank = &run.rank;
    rt_run_setup *setup = &run.setup;
    cmd->t_start = rt_now();
    cmd->start = time(NULL);
    cmd->argc = argc; /* before MPI_Init could touch them */
    cmd->argv = argv;
    rt_scene_init(&setup->scene);
    char err[1024] = "";

    /* 1. Options: every rank parses the same command line. */
    rt_cli_defaults(&cmd->opt);
    rt_cli_action action = rt_cli_parse(argc, argv, &cmd->opt, err, sizeof err);
    const rt_options *o = &cmd->opt;

    /* 2. MPI, when a launcher started this process. */
    if (rt_farm_init(&rank->farm, &argc, &argv) != 0) {
        fprintf(stderr, "rt-mpi: error: MPI initialisation failed\n");
        return RT_EXIT_RUNTIME;
    }
    rank->root = rank->farm.rank == 0;
    if (action == RT_CLI_DUMP_SCENE)
        return stop(&run, rank->root ? rt_run_dump_scene(o) : 0, "");
    if (action == RT_CLI_HELP || action == RT_CLI_VERSION || action == RT_CLI_LIST_SCENES)
        return stop(&run, answer(rank->root, action), "");

    /* 3. Checks before anything renders: rank 0 checks paths, memory and
     * checkpoint; every rank its threads. Then the scene: built on rank 0,
     * broadcast to all. A bad input ends every rank with one line. */
    int code = action == RT_CLI_ERROR ? RT_EXIT_USAGE : rt_run_check(cmd, rank, err, sizeof err), root_code;
    int mine = code;
    code = rt_farm_agree(&rank->farm, code, &root_code);
    if (mine && !root_code && err[0]) /* this rank alone: its own line */
        fprintf(stderr, "rt-mpi: error: rank %d: %s\n", rank->farm.rank, err);
    if (!code)
        code = rt_run_scene(o, rank, setup, err, sizeof err);
    if (code)
        return stop(&run, code, err);
    const double t_scene = rt_now();

    /* 4. Every rank builds the same renderer and job; rank 0 also the
     * framebuffer, the restored checkpoint and the hooks. */
    rt_run_renderer(o, rank, setup);
    rt_run_job(o, rank, setup);
    if (o->frame_job) { /* 4-6 for each frame of the range */
        rt_run_frames(&run);
        return stop(&run, 0, "");
    }
    if (rank->root)
        rt_run_root_init(o, rank, setup, &run.root);
    run.result.setup = rt_now() - t_scene;

    /* 5. The render, across every rank (a failure or signal ends the job
     * inside it). */
    rt_farm_render(&rank->farm, &setup->job, rank->root ? &run.root.own : NULL, &run.result.farm);
    rt_mem_settle(&run.root.fb);

    /* 6. Rank 0: image file, summary, reports. */
    if (rank->root)
        rt_run_finish(cmd, rank, setup, &run.root, &run.result);
    return stop(&run, 0, "");
}
