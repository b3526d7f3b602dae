/* start.c - the farm's start and end: MPI start-up (only under a
 * launcher), failure and exit for the whole job, the scene broadcast, and
 * the signal handlers every render loop watches. */
#include "internal.h"

#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifdef RT_HAVE_MPI
#include <mpi.h>

#include "inbox.h"
#endif

#include "clock.h"
#include "policy.h"
#include "status.h"

/* Set by the signal handler; every render loop watches it. */
static volatile sig_atomic_t g_stop;

static void on_signal(int sig) { g_stop = sig; }

void rt_farm_signals_install(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGUSR1, &sa, NULL);
}

const volatile sig_atomic_t *rt_farm_stop_flag(void) { return &g_stop; }

void rt_farm_stop_raise(int sig)
{
    if (!g_stop)
        g_stop = sig;
}

#ifdef RT_HAVE_MPI
/* Whether an MPI launcher started this process: mpirun (Open MPI, MPICH,
 * Intel MPI, MVAPICH) and srun with a PMI or PMIx plugin all leave one of
 * these in the environment. A process started by hand is a job of one rank
 * and needs no MPI: Open MPI would start it as a singleton, which forks an
 * orted and costs ~0.4 s of every command here. RT_MPI_INIT=1 forces
 * MPI_Init for a launcher this list does not know, 0 skips it. */
static int launched_by_mpi(void)
{
    static const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE", "PMI_FD",
                                       "PMI_PORT", "MPI_LOCALNRANKS", "MV2_COMM_WORLD_RANK"};
    const char *force = getenv("RT_MPI_INIT");
    if (force && *force)
        return strcmp(force, "0") != 0;
    for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++)
        if (getenv(vars[i]))
            return 1;
    return 0;
}
#endif

int rt_farm_init(rt_farm *f, int *argc, char ***argv)
{
    memset(f, 0, sizeof *f);
    f->size = f->mask_share = 1;
    rt_farm_place_init(f);
#ifdef RT_HAVE_MPI
    if (!launched_by_mpi())
        return RT_OK;
    int provided = 0;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
        return RT_EIO;
    f->mpi = 1;
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &f->rank);
    MPI_Comm_size(MPI_COMM_WORLD, &f->size);
    rt_farm_place_share(f);
    if (provided < MPI_THREAD_FUNNELED) {
        /* Only the main thread ever calls MPI, but with a lower level we
         * must not even run a second thread on rank 0. */
        if (f->size > 1)
            rt_farm_fail(f, RT_EXIT_RUNTIME, "MPI library provides no MPI_THREAD_FUNNELED support");
    }
#else
    (void)argc;
    (void)argv;
#endif
    return RT_OK;
}

const char *rt_farm_mpi_version(void)
{
#ifdef RT_HAVE_MPI
    /* One of the few MPI calls allowed before MPI_Init. */
    static char v[MPI_MAX_LIBRARY_VERSION_STRING];
    int len = 0;
    if (!v[0] && MPI_Get_library_version(v, &len) == MPI_SUCCESS) {
        v[len > 0 && len < (int)sizeof v ? len : 0] = 0;
        v[strcspn(v, "\n")] = 0;
    }
    return v[0] ? v : "unknown";
#else
    return "none";
#endif
}

void rt_farm_finalize(rt_farm *f)
{
#ifdef RT_HAVE_MPI
    if (f->mpi && f->lost) {
        /* A lost rank never reaches MPI_Finalize, and the others would wait
         * for it there: the work is saved, so the workers leave without it
         * and rank 0 ends the job, with status 0. */
        fflush(stdout);
        fflush(stderr);
        if (f->rank != 0)
            _exit(0);
        MPI_Abort(MPI_COMM_WORLD, 0);
    }
    if (f->mpi)
        MPI_Finalize();
#endif
    f->mpi = 0;
}

void rt_farm_exit(const rt_farm *f, rt_exit_code code)
{
    fflush(stdout);
    fflush(stderr);
#ifdef RT_HAVE_MPI
    /* Other ranks may be mid-render: a non-zero exit makes mpirun end them
     * (MPI_Abort would add its banner to an expected, documented stop). */
    if (f->mpi && f->size > 1)
        _exit(code);
    if (f->mpi)
        MPI_Finalize();
#else
    (void)f;
#endif
    exit(code);
}

/* What rt_farm_fail runs first (rt_farm_on_fail). */
static void (*g_on_fail)(void *);
static void *g_on_fail_ctx;

void rt_farm_on_fail(void (*fn)(void *), void *ctx)
{
    g_on_fail = fn;
    g_on_fail_ctx = ctx;
}

void rt_farm_fail(const rt_farm *f, rt_exit_code code, const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    void (*on_fail)(void *) = g_on_fail;
    g_on_fail = NULL; /* once, even if it fails in turn */
    if (on_fail)
        on_fail(g_on_fail_ctx);
    if (f->size > 1)
        fprintf(stderr, "rt-mpi: error: rank %d: %s\n", f->rank, msg);
    else
        fprintf(stderr, "rt-mpi: error: %s\n", msg);
    fflush(stderr);
#ifdef RT_HAVE_MPI
    if (f->mpi && f->size > 1)
        MPI_Abort(MPI_COMM_WORLD, code);
    if (f->mpi)
        MPI_Finalize();
#endif
    exit(code);
}

#ifdef RT_HAVE_MPI
/* Completes one of the start-up's collectives (the checks' verdict, the
 * scene, the common start). MPI's blocking calls would wait forever for a
 * rank lost before rendering began: Open MPI 4.1 has no ULFM, and under
 * mpirun --enable-recovery or srun --no-kill nothing ends the job. So rank
 * 0, which waits on the others there only for their checks, the scene's
 * transfer and their set-up, ends it with one line after
 * RT_POLICY_START_WAIT s; the workers wait as long as rank 0 takes (it may
 * be reading a large scene). Napping between tests: no core spins. */
static void start_wait(const rt_farm *f, MPI_Request *req, int rc, const char *step)
{
    int wait_s = RT_POLICY_START_WAIT;
#ifdef RT_TEST_HOOKS
    /* Test builds only: a shorter wait (tests/e2e/e2e_survival.sh) */
    const char *w = getenv("RT_TEST_START_WAIT");
    if (w && atoi(w) > 0)
        wait_s = atoi(w);
#endif
    const double give_up = rt_now() + wait_s;
    int done = 0, idle = 0;
    for (;;) {
        if (rc != MPI_SUCCESS || (rc = MPI_Test(req, &done, MPI_STATUS_IGNORE)) != MPI_SUCCESS)
            rt_farm_fail(f, RT_EXIT_RUNTIME, "%s failed", step);
        if (done)
            return;
        if (f->rank == 0 && rt_now() > give_up)
            rt_farm_fail(f, RT_EXIT_RUNTIME,
                         "not every rank reached the start-up's %s within %d s: a rank was lost before rendering "
                         "began; the job ends (run it again)",
                         step, wait_s);
        rt_inbox_nap(&idle);
    }
}

static void bcast(const rt_farm *f, void *buf, int n, MPI_Datatype type, const char *step)
{
    MPI_Request req;
    start_wait(f, &req, MPI_Ibcast(buf, n, type, 0, MPI_COMM_WORLD, &req), step);
}
#endif

void rt_farm_sync(const rt_farm *f)
{
#ifdef RT_HAVE_MPI
#ifdef RT_TEST_HOOKS
    /* Test builds only: one rank dies as a crash would, before the start */
    const char *die = getenv("RT_TEST_DIE_AT_START");
    if (die && *die && atoi(die) == f->rank)
        raise(SIGKILL);
#endif
    if (f->mpi && f->size > 1) {
        MPI_Request req;
        start_wait(f, &req, MPI_Ibarrier(MPI_COMM_WORLD, &req), "common start (MPI_Ibarrier)");
    }
#else
    (void)f;
#endif
}

int rt_farm_agree(const rt_farm *f, int mine, int *root)
{
    *root = mine;
#ifdef RT_HAVE_MPI
    if (f->mpi && f->size > 1) {
        int worst = mine;
        MPI_Request req;
        start_wait(f, &req, MPI_Iallreduce(&mine, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD, &req),
                   "checks (MPI_Iallreduce)");
        bcast(f, root, 1, MPI_INT, "checks (MPI_Ibcast)");
        return worst;
    }
#else
    (void)f;
#endif
    return mine;
}

void rt_farm_bcast_int(const rt_farm *f, int *v)
{
#ifdef RT_HAVE_MPI
    if (f->mpi && f->size > 1)
        bcast(f, v, 1, MPI_INT, "broadcast (MPI_Ibcast)");
#else
    (void)f;
    (void)v;
#endif
}

int rt_farm_bcast_bytes(const rt_farm *f, uint8_t **buf, size_t *len)
{
#ifdef RT_HAVE_MPI
    if (!f->mpi || f->size == 1)
        return RT_OK;
    unsigned long long n = f->rank == 0 ? (unsigned long long)*len : 0;
    bcast(f, &n, 1, MPI_UNSIGNED_LONG_LONG, "scene's size (MPI_Ibcast)");
    if (n > (unsigned long long)INT32_MAX)
        rt_farm_fail(f, RT_EXIT_RUNTIME, "scene of %llu bytes is too large to broadcast", n);
    if (f->rank != 0) {
        *buf = malloc(n ? n : 1);
        if (!*buf)
            rt_farm_fail(f, RT_EXIT_RUNTIME, "out of memory for the %llu-byte scene", n);
        *len = (size_t)n;
    }
    bcast(f, *buf, (int)n, MPI_BYTE, "scene (MPI_Ibcast)");
#else
    (void)f;
    (void)buf;
    (void)len;
#endif
    return RT_OK;
}

