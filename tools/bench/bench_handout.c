/* bench_handout.c - how fast rank 0 can hand out empty units, and what each
 * costs it in CPU (issue 26, point 2; docs/notes/handout.md). No rendering:
 * a worker "renders" a unit by spinning --spin-us (default 0).
 *
 *   mpirun -np N ... bench_handout --scheme p2p|rma [options]
 *
 *   --units N      units to hand out (default 20000)
 *   --spin-us S    a worker's time per unit, busy (default 0)
 *   --chunk C      units per request (p2p: a worker reports, and so asks,
 *                  once C are done; rma: the fetch-and-op adds C); default 1
 *   --prefetch P   p2p: units a worker keeps in flight (its HELLO asks for
 *                  P; default 2 = the farm's); must be >= chunk
 *   --root poll|block   rma: what rank 0 does meanwhile: poll = the farm's
 *                  loop (MPI_Iprobe twice, nap 50 us doubling to 1 ms, the
 *                  reports received); block = sits in blocking MPI calls
 *                  (Open MPI busy-polls in them: full progress, a full core)
 *   --reports 0|1  rma: a worker sends rank 0 a report (32 bytes a unit,
 *                  like the farm's) after each chunk (default 1): without
 *                  it rank 0 never learns who holds which unit
 *
 * p2p is the farm's wire (src/farm/server.c, worker.c, msg.c): HELLO asks
 * for P units, each REPORT (4 int64 a unit) asks for as many more, rank 0
 * answers with UNITS (7 uint32 a unit) by MPI_Isend and keeps a ledger
 * (owner and state of each unit), checking every report against it. The
 * worker sends its reports once it has C done or nothing left to do, and
 * naps like the farm's worker when it has nothing.
 *
 * rma: a 64-bit counter in rank 0's memory (MPI_Win_allocate), every rank
 * in MPI_Win_lock_all (passive target); a worker takes [v, v + C) by
 * MPI_Fetch_and_op(MPI_SUM, C) + MPI_Win_flush until v >= N. With reports,
 * rank 0 marks each reported unit in the same ledger (owner = the sender).
 *
 * Wall time is rank 0's, from before the start barrier to the last
 * report (or, without reports, to the end barrier). Rank 0's CPU is
 * getrusage over the same span: RUSAGE_THREAD (its main thread, as the
 * farm's serve_cpu) and RUSAGE_SELF (all its threads). Rank 0 prints one
 * line of JSON, with the osc component the window got (Open MPI 4.1 names
 * windows after it). */
#define _GNU_SOURCE
#include <mpi.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "inbox.h" /* the farm's nap and probe: rt_inbox_nap, rt_inbox_probe */

enum { TAG_HELLO = 11, TAG_REPORT, TAG_UNITS, TAG_FINISH };
#define MSG_REPORT 4
#define MSG_UNIT 7

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double cpu(int who)
{
    struct rusage ru;
    if (getrusage(who, &ru) != 0)
        return 0;
    return (double)ru.ru_utime.tv_sec + 1e-6 * ru.ru_utime.tv_usec + (double)ru.ru_stime.tv_sec +
           1e-6 * ru.ru_stime.tv_usec;
}

static void spin(double us)
{
    if (us <= 0)
        return;
    double end = now() + us * 1e-6;
    while (now() < end)
        ;
}

static void die(const char *what)
{
    fprintf(stderr, "bench_handout: %s\n", what);
    MPI_Abort(MPI_COMM_WORLD, 2);
}

typedef struct opts {
    long units;
    double spin_us;
    int chunk, prefetch, block, reports;
    const char *scheme;
} opts;

/* Rank 0's ledger: who holds each unit and whether it is done. */
typedef struct ledger {
    int32_t *owner;
    uint8_t *done;
    long n_done;
} ledger;

static void ledger_init(ledger *L, long n)
{
    L->owner = malloc((size_t)n * sizeof *L->owner);
    L->done = calloc((size_t)n, 1);
    if (!L->owner || !L->done)
        die("out of memory");
    for (long i = 0; i < n; i++)
        L->owner[i] = -1;
    L->n_done = 0;
}

/* A report of count int64 from r: each unit must be r's (p2p) or unowned
 * (rma: rank 0 learns the owner here). Returns the units reported. */
static int ledger_report(ledger *L, long n, int r, const int64_t *m, int count, int claim)
{
    if (count % MSG_REPORT)
        die("malformed report");
    for (int k = 0; k < count; k += MSG_REPORT) {
        int64_t id = m[k];
        if (id < 0 || id >= n || L->done[id] || (claim ? L->owner[id] != -1 : L->owner[id] != r))
            die("report of a unit the rank does not hold");
        L->owner[id] = r;
        L->done[id] = 1;
        L->n_done++;
    }
    return count / MSG_REPORT;
}

/* --- p2p: the farm's request/reply ----------------------------------- */

typedef struct outgoing {
    MPI_Request req;
    uint32_t *buf;
} outgoing;

typedef struct root {
    const opts *o;
    ledger L;
    long next; /* next unit to hand out */
    int *credit, *finish_sent;
    outgoing *outbox;
    int n_out, cap_out;
    long msgs_in, msgs_out;
    int n_finish;   /* FINISH sent */
    double t_done;  /* when the last unit was reported */
} root;

static void reap(root *s)
{
    for (int i = 0; i < s->n_out;) {
        int done = 0;
        MPI_Test(&s->outbox[i].req, &done, MPI_STATUS_IGNORE);
        if (done) {
            free(s->outbox[i].buf);
            s->outbox[i] = s->outbox[--s->n_out];
        } else {
            i++;
        }
    }
}

static void post(root *s, int r, int tag, uint32_t *buf, int count)
{
    if (s->n_out == s->cap_out) {
        s->cap_out = s->cap_out ? 2 * s->cap_out : 16;
        s->outbox = realloc(s->outbox, (size_t)s->cap_out * sizeof *s->outbox);
        if (!s->outbox)
            die("out of memory");
    }
    outgoing *o = &s->outbox[s->n_out++];
    o->buf = buf;
    MPI_Isend(buf, count, MPI_UINT32_T, r, tag, MPI_COMM_WORLD, &o->req);
    s->msgs_out++;
}

static void serve_peer(root *s, int r)
{
    long n = s->o->units - s->next;
    if (n > s->credit[r])
        n = s->credit[r];
    if (n > 0) {
        uint32_t *m = malloc((size_t)n * MSG_UNIT * sizeof *m);
        if (!m)
            die("out of memory");
        for (long k = 0; k < n; k++) {
            long id = s->next++;
            s->L.owner[id] = r;
            uint32_t *u = m + k * MSG_UNIT;
            u[0] = (uint32_t)id, u[1] = 0, u[2] = 1, u[3] = 0, u[4] = 64, u[5] = 0, u[6] = 1;
        }
        s->credit[r] -= (int)n;
        post(s, r, TAG_UNITS, m, (int)(n * MSG_UNIT));
    } else if (s->next == s->o->units && !s->finish_sent[r]) {
        s->finish_sent[r] = 1;
        s->n_finish++;
        post(s, r, TAG_FINISH, NULL, 0);
    }
}

static void root_p2p(const opts *o, int size, root *s)
{
    memset(s, 0, sizeof *s);
    s->o = o;
    ledger_init(&s->L, o->units);
    s->credit = calloc((size_t)size, sizeof(int));
    s->finish_sent = calloc((size_t)size, sizeof(int));
    int64_t *buf = NULL;
    int cap = 0, idle = 0;
    /* a worker whose HELLO comes after the last report still needs FINISH */
    while (s->L.n_done < o->units || s->n_finish < size - 1) {
        if (s->L.n_done == o->units && !s->t_done)
            s->t_done = now();
        reap(s);
        int flag = 0;
        MPI_Status st;
        rt_inbox_probe(MPI_ANY_SOURCE, &flag, &st);
        if (!flag) {
            rt_inbox_nap(&idle);
            continue;
        }
        idle = 0;
        int count, r = st.MPI_SOURCE;
        MPI_Get_count(&st, st.MPI_TAG == TAG_HELLO ? MPI_INT32_T : MPI_INT64_T, &count);
        if (count > cap) {
            cap = count;
            buf = realloc(buf, (size_t)cap * sizeof *buf);
        }
        s->msgs_in++;
        if (st.MPI_TAG == TAG_HELLO) {
            int32_t want;
            MPI_Recv(&want, 1, MPI_INT32_T, r, TAG_HELLO, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            s->credit[r] = want;
        } else if (st.MPI_TAG == TAG_REPORT) {
            MPI_Recv(buf, count, MPI_INT64_T, r, TAG_REPORT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            s->credit[r] += ledger_report(&s->L, o->units, r, buf, count, 0);
        } else {
            die("unexpected tag");
        }
        serve_peer(s, r);
    }
    if (!s->t_done)
        s->t_done = now();
    for (int i = 0; i < s->n_out; i++)
        MPI_Wait(&s->outbox[i].req, MPI_STATUS_IGNORE);
    reap(s);
    free(buf);
}

static void send_reports(int64_t *rep, int *n_rep)
{
    if (*n_rep) {
        MPI_Send(rep, *n_rep * MSG_REPORT, MPI_INT64_T, 0, TAG_REPORT, MPI_COMM_WORLD);
        *n_rep = 0;
    }
}

static long worker_p2p(const opts *o)
{
    const int P = o->prefetch, C = o->chunk;
    uint32_t *queue = malloc((size_t)P * sizeof *queue), *m = malloc((size_t)P * MSG_UNIT * sizeof *m);
    int64_t *rep = malloc((size_t)P * MSG_REPORT * sizeof *rep);
    int qhead = 0, qlen = 0, n_rep = 0, finished = 0, idle = 0;
    long done = 0;
    double t0 = now();
    int32_t want = P;
    MPI_Send(&want, 1, MPI_INT32_T, 0, TAG_HELLO, MPI_COMM_WORLD);
    while (!finished || qlen || n_rep) {
        if (qlen) {
            uint32_t id = queue[qhead];
            qhead = (qhead + 1) % P, qlen--;
            double a = now() - t0;
            spin(o->spin_us);
            int64_t *r = rep + (size_t)n_rep++ * MSG_REPORT;
            r[0] = id, r[1] = 0, r[2] = (int64_t)(a * 1e9), r[3] = (int64_t)((now() - t0) * 1e9);
            done++;
        }
        if (n_rep >= C || (!qlen && n_rep))
            send_reports(rep, &n_rep);
        int got = 0;
        for (;;) {
            int flag = 0;
            MPI_Status st;
            rt_inbox_probe(0, &flag, &st);
            if (!flag)
                break;
            got = 1;
            if (st.MPI_TAG == TAG_FINISH) {
                MPI_Recv(NULL, 0, MPI_UINT32_T, 0, TAG_FINISH, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
                finished = 1;
                continue;
            }
            int count;
            MPI_Get_count(&st, MPI_UINT32_T, &count);
            if (st.MPI_TAG != TAG_UNITS || count % MSG_UNIT || qlen + count / MSG_UNIT > P)
                die("unexpected message from rank 0");
            MPI_Recv(m, count, MPI_UINT32_T, 0, TAG_UNITS, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            for (int k = 0; k < count; k += MSG_UNIT)
                queue[(qhead + qlen++) % P] = m[k];
        }
        if (got)
            idle = 0;
        else if (!qlen && !n_rep && !finished)
            rt_inbox_nap(&idle);
    }
    free(queue);
    free(m);
    free(rep);
    return done;
}

/* --- rma: an atomic counter in rank 0's memory ------------------------ */

static long worker_rma(const opts *o, MPI_Win win)
{
    const int64_t C = o->chunk;
    int64_t *rep = malloc((size_t)C * MSG_REPORT * sizeof *rep);
    long done = 0;
    double t0 = now();
    for (;;) {
        int64_t first = 0;
        MPI_Fetch_and_op(&C, &first, MPI_INT64_T, 0, 0, MPI_SUM, win);
        MPI_Win_flush(0, win);
        if (first >= o->units)
            break;
        int64_t end = first + C < o->units ? first + C : o->units;
        int n = 0;
        for (int64_t id = first; id < end; id++, n++) {
            double a = now() - t0;
            spin(o->spin_us);
            int64_t *r = rep + (size_t)n * MSG_REPORT;
            r[0] = id, r[1] = 0, r[2] = (int64_t)(a * 1e9), r[3] = (int64_t)((now() - t0) * 1e9);
        }
        done += n;
        if (o->reports)
            MPI_Send(rep, n * MSG_REPORT, MPI_INT64_T, 0, TAG_REPORT, MPI_COMM_WORLD);
    }
    free(rep);
    return done;
}

/* Rank 0 under rma: receives the reports (if any) and waits for the end
 * barrier, either polling like the farm or blocked in MPI. */
static long root_rma(const opts *o, ledger *L, MPI_Request *end)
{
    long msgs = 0;
    int64_t *buf = malloc((size_t)o->chunk * MSG_REPORT * sizeof *buf);
    int idle = 0;
    if (o->reports)
        ledger_init(L, o->units);
    while (o->reports && L->n_done < o->units) {
        MPI_Status st;
        int flag = 0;
        if (o->block) {
            MPI_Probe(MPI_ANY_SOURCE, TAG_REPORT, MPI_COMM_WORLD, &st);
            flag = 1;
        } else {
            rt_inbox_probe(MPI_ANY_SOURCE, &flag, &st);
        }
        if (!flag) {
            rt_inbox_nap(&idle);
            continue;
        }
        idle = 0;
        int count;
        MPI_Get_count(&st, MPI_INT64_T, &count);
        if (st.MPI_TAG != TAG_REPORT || count > o->chunk * MSG_REPORT)
            die("unexpected message");
        MPI_Recv(buf, count, MPI_INT64_T, st.MPI_SOURCE, TAG_REPORT, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        msgs++;
        ledger_report(L, o->units, st.MPI_SOURCE, buf, count, 1);
    }
    if (!o->reports) {
        if (o->block) {
            MPI_Wait(end, MPI_STATUS_IGNORE);
        } else {
            for (;;) {
                int flag = 0;
                MPI_Test(end, &flag, MPI_STATUS_IGNORE);
                if (flag)
                    break;
                MPI_Status st;
                rt_inbox_probe(MPI_ANY_SOURCE, &flag, &st); /* the farm's loop: nothing comes */
                rt_inbox_nap(&idle);
            }
        }
    }
    free(buf);
    return msgs;
}

/* Waits for a request without spinning a core (the box has 2 cores). */
static void wait_napping(MPI_Request *req)
{
    for (;;) {
        int flag = 0;
        MPI_Test(req, &flag, MPI_STATUS_IGNORE);
        if (flag)
            return;
        struct timespec ts = {0, 200000L};
        nanosleep(&ts, NULL);
    }
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank, size;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    opts o = {20000, 0, 1, 2, 0, 1, "p2p"};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v)
            die("option without value");
        if (!strcmp(a, "--units"))
            o.units = atol(v);
        else if (!strcmp(a, "--spin-us"))
            o.spin_us = atof(v);
        else if (!strcmp(a, "--chunk"))
            o.chunk = atoi(v);
        else if (!strcmp(a, "--prefetch"))
            o.prefetch = atoi(v);
        else if (!strcmp(a, "--root"))
            o.block = !strcmp(v, "block");
        else if (!strcmp(a, "--reports"))
            o.reports = atoi(v);
        else if (!strcmp(a, "--scheme"))
            o.scheme = v;
        else
            die("unknown option (see the comment at the top of bench_handout.c)");
        i++;
    }
    const int rma = !strcmp(o.scheme, "rma");
    if (size < 2 || o.units < 1 || o.chunk < 1 || (!rma && o.prefetch < o.chunk) ||
        (!rma && strcmp(o.scheme, "p2p")))
        die("needs 2 ranks or more, --scheme p2p|rma, units >= 1, chunk >= 1, prefetch >= chunk");

    MPI_Win win = MPI_WIN_NULL;
    int64_t *counter = NULL;
    if (rma) {
        MPI_Win_allocate(rank == 0 ? (MPI_Aint)sizeof(int64_t) : 0, sizeof(int64_t), MPI_INFO_NULL, MPI_COMM_WORLD,
                         &counter, &win);
        if (rank == 0)
            *counter = 0;
        MPI_Win_lock_all(MPI_MODE_NOCHECK, win);
    }
    /* The clock starts before the last barrier: with osc/pt2pt or ucx,
     * rank 0 still inside a barrier that the workers have left serves their
     * fetches (seen once: 130000 units "in" 0.4 ms when it started after). */
    MPI_Barrier(MPI_COMM_WORLD);
    double t0 = now(), c_thread = cpu(RUSAGE_THREAD), c_self = cpu(RUSAGE_SELF);
    MPI_Barrier(MPI_COMM_WORLD);
    long msgs_in = 0, msgs_out = 0, mine = 0;
    MPI_Request end;
    double t_done = 0;
    if (rank == 0) {
        if (rma) {
            MPI_Ibarrier(MPI_COMM_WORLD, &end);
            ledger L = {0};
            msgs_in = root_rma(&o, &L, &end);
            free(L.owner);
            free(L.done);
        } else {
            root s;
            root_p2p(&o, size, &s);
            msgs_in = s.msgs_in, msgs_out = s.msgs_out, t_done = s.t_done;
            free(s.L.owner);
            free(s.L.done);
            free(s.credit);
            free(s.finish_sent);
            free(s.outbox);
        }
    } else {
        mine = rma ? worker_rma(&o, win) : worker_p2p(&o);
        if (rma)
            MPI_Ibarrier(MPI_COMM_WORLD, &end);
    }
    double wall = now() - t0;
    if (rank == 0 && !rma)
        wall = t_done - t0;
    c_thread = cpu(RUSAGE_THREAD) - c_thread;
    c_self = cpu(RUSAGE_SELF) - c_self;
    if (rma) {
        if (rank == 0 && o.reports)
            MPI_Wait(&end, MPI_STATUS_IGNORE);
        else if (rank != 0)
            wait_napping(&end);
    }
    /* every unit exactly once */
    long total = 0;
    MPI_Reduce(&mine, &total, 1, MPI_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
    /* the osc component: Open MPI 4.1 names a window after it ("rdma
     * window 3"); osc/sm leaves it empty */
    char osc[MPI_MAX_OBJECT_NAME] = "-";
    if (rma && rank == 0) {
        int len = 0;
        MPI_Win_get_name(win, osc, &len);
        char *sp = strchr(osc, ' ');
        if (sp)
            *sp = 0;
        else if (!len)
            strcpy(osc, "sm"); /* the one that names no window (4.1) */
    }
    if (rank == 0) {
        if (total != o.units)
            die("the workers did not do every unit exactly once");
        printf("{\"scheme\": \"%s\", \"np\": %d, \"chunk\": %d, \"prefetch\": %d, \"root\": \"%s\", "
               "\"reports\": %d, \"units\": %ld, \"spin_us\": %g, \"wall_s\": %.6f, \"units_per_s\": %.1f, "
               "\"root_cpu_thread_s\": %.6f, \"root_cpu_self_s\": %.6f, \"root_cpu_us_per_unit\": %.3f, "
               "\"root_cpu_frac\": %.3f, \"root_msgs_in\": %ld, \"root_msgs_out\": %ld, \"osc\": \"%s\"}\n",
               o.scheme, size, o.chunk, rma ? 0 : o.prefetch, rma ? (o.block ? "block" : "poll") : "poll",
               rma ? o.reports : 1, o.units, o.spin_us, wall, (double)o.units / wall, c_thread, c_self,
               1e6 * c_thread / (double)o.units, c_thread / wall, msgs_in, msgs_out, osc);
    }
    if (rma) {
        MPI_Win_unlock_all(win);
        MPI_Win_free(&win);
    }
    MPI_Finalize();
    return 0;
}
