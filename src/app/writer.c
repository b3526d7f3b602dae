/* writer.c - rank 0's writer thread in a frame job (issue 37). When a
 * frame's last sums are in, the main thread hands the frame over (its
 * options, its framebuffer of sums and its stats, moved, not copied) and
 * serves on at once; this thread converts the sums, writes the files (the
 * same writers as one image: temp + rename) and prints the frame's summary
 * and --stats, in the order the frames were handed over. It never calls MPI (the farm
 * runs MPI_THREAD_FUNNELED): a failed write is kept and the main thread
 * ends the job with it, at the next hand-over or at the end.
 *
 * The checkpoint is the main thread's (the frames in flight, sequence.c):
 * the writer never writes or removes it. A frame whose file is not written
 * yet when the job stops is simply rendered again on --resume (files
 * decide: sequence.c skips the frames whose files exist). When the main
 * thread ends the job with a failure (rt_farm_fail), the writer is joined
 * first (rt_farm_on_fail): the file being written is finished, no temp
 * file is left behind. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mem.h"
#include "run.h"
#include "status.h"

typedef struct item {
    rt_run_cmd cmd;       /* the frame's copy: its options (pointing into paths) */
    rt_frame_paths paths; /* its files */
    rt_run_root root;     /* its framebuffer of sums */
    rt_run_result result;
    rt_run_lists lists;
    int last;
} item;

struct rt_run_writer {
    pthread_t thread;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    const rt_run_rank *rank;
    const rt_run_setup *setup;
    item *queue[RT_RUN_WRITER_QUEUE]; /* waiting, oldest first */
    unsigned waiting;
    int closing, dropping; /* no more frames come; drop the waiting ones */
    uint32_t held, peak;   /* framebuffers on rank 0: now, at most */
    int failed;
    rt_run_fault fault;
    uint64_t last_hash; /* of the frame handed over with `last` */
};

static void item_free(item *it)
{
    rt_run_release(&it->root, &it->result);
    free(it);
}

static void *writer_main(void *arg)
{
    rt_run_writer *w = arg;
    pthread_mutex_lock(&w->mu);
    for (;;) {
        while (!w->waiting && !w->closing)
            pthread_cond_wait(&w->cv, &w->mu);
        if (!w->waiting || w->dropping)
            break;
        item *it = w->queue[0];
        memmove(w->queue, w->queue + 1, --w->waiting * sizeof *w->queue);
        pthread_cond_broadcast(&w->cv); /* a place in the queue */
        rt_run_fault fault;
        const rt_run_finish_how how = {
            .lists = it->lists, .fault = &fault, .frames_peak = w->peak, .hash = it->last ? &w->last_hash : NULL};
        const int failed = w->failed;
        pthread_mutex_unlock(&w->mu);
        /* after a failed write, the later frames are dropped (not written) */
        const int st = failed ? 0 : rt_run_finish_frame(&it->cmd, w->rank, w->setup, &it->root, &it->result, &how);
        item_free(it);
        pthread_mutex_lock(&w->mu);
        w->held--;
        if (st && !w->failed) {
            w->failed = 1;
            w->fault = fault;
        }
        pthread_cond_broadcast(&w->cv);
    }
    pthread_mutex_unlock(&w->mu);
    return NULL;
}

static void end(rt_run_writer *w, int drop);

/* rt_farm_fail from the main thread: the file being written is finished,
 * the waiting frames dropped, quietly (the failure has its line). */
static void abandon(void *arg)
{
    end(arg, 1);
    free(arg);
}

rt_run_writer *rt_run_writer_start(const rt_run_rank *rank, const rt_run_setup *s)
{
    rt_run_writer *w = calloc(1, sizeof *w);
    if (!w)
        rt_farm_fail(&rank->farm, RT_EXIT_RUNTIME, "out of memory");
    w->rank = rank;
    w->setup = s;
    (void)rt_farm_mpi_version(); /* cached now, by the thread that may call MPI */
    if (pthread_mutex_init(&w->mu, NULL) || pthread_cond_init(&w->cv, NULL) ||
        pthread_create(&w->thread, NULL, writer_main, w))
        rt_farm_fail(&rank->farm, RT_EXIT_RUNTIME, "cannot start the writer thread");
    rt_farm_on_fail(abandon, w);
    return w;
}


void rt_run_writer_hold(rt_run_writer *w)
{
    pthread_mutex_lock(&w->mu);
    if (++w->held > w->peak)
        w->peak = w->held;
    pthread_mutex_unlock(&w->mu);
}

/* The main thread: an earlier frame's write failed, the job ends. */
static void check_failed(rt_run_writer *w)
{
    if (w->failed)
        rt_farm_fail(&w->rank->farm, w->fault.code, "%s", w->fault.msg);
}

void rt_run_writer_put(rt_run_writer *w, const rt_run_cmd *cmd, const rt_options *fo, const rt_frame_paths *paths,
                       rt_run_root *root, rt_run_result *result, int last)
{
    item *it = malloc(sizeof *it);
    if (!it)
        rt_farm_fail(&w->rank->farm, RT_EXIT_RUNTIME, "out of memory");
    it->cmd = *cmd;
    it->paths = *paths;
    /* fo's files point into `paths`: the same names again, into the copy */
    if (rt_cli_frames_paths(&cmd->opt, fo->frame, &it->cmd.opt, &it->paths) != RT_OK) /* as fo: cannot fail */
        rt_farm_fail(&w->rank->farm, RT_EXIT_RUNTIME, "frame %u: file name too long", fo->frame);
    it->cmd.opt.resume = fo->resume;
    it->cmd.opt.keep_checkpoint = fo->keep_checkpoint;
    it->cmd.opt.done_file = fo->done_file;
    it->root = *root;
    it->result = *result;
    it->lists = rt_run_lists_of(w->setup);
    it->last = last;
    memset(root, 0, sizeof *root);
    memset(result, 0, sizeof *result);
    pthread_mutex_lock(&w->mu);
    /* Full (RT_RUN_WRITER_QUEUE frames waiting): rank 0's main thread waits
     * here for the writer, and the frame it hands over still counts in the
     * farm's cap meanwhile (it is released after this returns). This
     * bounds rank 0's memory to RT_RUN_FRAMES_HELD frames: the cap's, the
     * queue and the frame being written. */
    while (w->waiting == RT_RUN_WRITER_QUEUE && !w->failed)
        pthread_cond_wait(&w->cv, &w->mu);
    if (!w->failed) {
        w->queue[w->waiting++] = it;
        it = NULL;
        pthread_cond_broadcast(&w->cv);
    }
    pthread_mutex_unlock(&w->mu);
    if (it) {
        item_free(it);
        check_failed(w);
    }
}

static void end(rt_run_writer *w, int drop)
{
    rt_farm_on_fail(NULL, NULL);
    pthread_mutex_lock(&w->mu);
    w->closing = 1;
    w->dropping = drop;
    pthread_cond_broadcast(&w->cv);
    pthread_mutex_unlock(&w->mu);
    pthread_join(w->thread, NULL);
    while (w->waiting)
        item_free(w->queue[--w->waiting]);
    pthread_cond_destroy(&w->cv);
    pthread_mutex_destroy(&w->mu);
}

void rt_run_writer_finish(rt_run_writer *w, uint64_t *last_hash, uint32_t *peak)
{
    end(w, 0);
    *last_hash = w->last_hash;
    *peak = w->peak;
    if (w->failed) {
        const rt_run_fault fault = w->fault;
        const rt_farm *f = &w->rank->farm;
        free(w);
        rt_farm_fail(f, fault.code, "%s", fault.msg);
    }
    free(w);
}

void rt_run_writer_stop(rt_run_writer *w)
{
    end(w, 1);
    if (w->failed) /* the job stops anyway (exit 75), but the user is told */
        fprintf(stderr, "rt-mpi: error: %s\n", w->fault.msg);
    free(w);
}
