/* checks.c - what is verified before anything renders: rank 0 checks the
 * output and checkpoint paths, the memory the image needs and whether a
 * checkpoint is in the way; every rank settles its thread count (and binds
 * its threads). Bad input is one error line and an exit code, found here
 * rather than after an hour of rendering. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "run.h"
#include "status.h"

/* Threads from the environment when -j is 0: OMP_NUM_THREADS if it is set
 * (it must then be a positive whole number), else the rank's cores. */
static int pick_threads(const rt_farm *f, const rt_options *o, char *err, size_t errlen)
{
    if (o->threads > 0)
        return o->threads;
    const char *env = getenv("OMP_NUM_THREADS");
    if (env && *env) {
        uint64_t v;
        if (rt_cli_parse_u64(env, 1, 4096, &v) != RT_OK) {
            snprintf(err, errlen, "OMP_NUM_THREADS='%s' is not a whole number from 1 to 4096", env);
            return -1;
        }
        return (int)v;
    }
    return rt_farm_default_threads(f);
}

/* Refuse up front a framebuffer the machine cannot hold: rank 0 keeps 8
 * bytes per value of a pixel's sums (3, or the wide layout's ch and the
 * 3-sum image made from them, job.h), 3 bytes of 8-bit output for the
 * hash, and the output format's own pixels (up to 12 bytes: float RGB). */
static int check_memory(const rt_job *j, char *err, size_t errlen)
{
    const uint32_t ch = rt_job_layout(j).ch, sums = ch > 3 ? ch + 3 : ch;
    double need = (double)j->width * j->height * (sums * sizeof(int64_t) + 3 + 12);
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    double have = pages > 0 && page > 0 ? (double)pages * (double)page : 0;
    if (have > 0 && need > 0.9 * have) {
        snprintf(err, errlen,
                 "a %u x %u image needs about %.1f GiB of memory on rank 0, more than this machine has "
                 "(%.1f GiB)",
                 j->width, j->height, need / 1073741824.0, have / 1073741824.0);
        return -1;
    }
    return 0;
}

/* Warnings that do not stop the run. */
static void warn_placement(const rt_options *o, const rt_farm *f)
{
    if (f->omp_bound && f->mask_share > 1)
        fprintf(stderr, "rt-mpi: warning: OMP_PROC_BIND is set and %d ranks of a node share the same CPUs: each binds "
                        "its threads from the first place on, onto the same cores (give each rank its own cores, e.g. "
                        "mpirun --map-by slot:PE=N, or unset OMP_PROC_BIND)\n",
                f->mask_share);
    if (o->threads > f->cores)
        fprintf(stderr, "rt-mpi: warning: -j %d is more than the %d cores available; threads will share cores\n",
                o->threads, f->cores);
}

rt_exit_code rt_run_check(rt_run_cmd *cmd, rt_run_rank *rank, char *err, size_t errlen)
{
    rt_options *o = &cmd->opt;
    if (!o->no_checkpoint && !o->checkpoint) {
        snprintf(cmd->ckpt_default, sizeof cmd->ckpt_default, "%s.ckpt", o->output);
        o->checkpoint = cmd->ckpt_default;
    }
    rt_exit_code code = RT_EXIT_OK;
    if (rank->root && (o->frame_job ? rt_cli_frames_check(o, err, errlen) : rt_cli_check_output(o, err, errlen)) != RT_OK)
        code = RT_EXIT_USAGE;
    if (!code && rank->root && check_memory(&o->job, err, errlen) != 0)
        code = RT_EXIT_USAGE;
    if (!code && rank->root && o->checkpoint)
        code = rt_run_ckpt_check(o, err, errlen);
    if (!code) {
        rank->threads = pick_threads(&rank->farm, o, err, errlen);
        if (rank->threads < 0)
            code = RT_EXIT_USAGE;
        else
            rank->bound = rt_farm_bind_threads(&rank->farm, rank->threads);
    }
#ifndef RT_HAVE_EMBREE
    if (!code && o->accel == RT_ACCEL_EMBREE) {
        snprintf(err, errlen, "--accel embree: this build has no Embree (configure with -DRT_EMBREE=ON)");
        code = RT_EXIT_USAGE;
    }
#endif
    if (!code && rank->root)
        warn_placement(o, &rank->farm);
    return code;
}
