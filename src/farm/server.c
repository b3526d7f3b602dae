/* server.c - rank 0's main thread under MPI: hands out units and takes in
 * reports and sums, calling the hooks in between. It never blocks in MPI
 * (Open MPI busy-polls inside blocking receives): it probes and sleeps with
 * a short back-off, so it costs next to no CPU while rank 0's render thread
 * works.
 *
 * Each worker asks for a few units up front; each unit it reports done is
 * its request for one more, so a slow rank gets fewer. The sums do not come
 * unit by unit: a worker keeps them (held.h) and sends them combined, when
 * rank 0 asks (a progressive pass is done, a checkpoint is due, nothing is
 * left to hand out), when it holds enough, or at its flush interval.
 *
 * A worker rank 0 has not heard from for a lease (it sends a beat while it
 * has nothing else to say) is lost: the ledger queues its units again for
 * the others, and whatever it sends later is dropped. The image is the same
 * bytes: every unit's sums enter it exactly once. */
#include "inbox.h"
#include "internal.h"
#include "msg.h"
#include "policy.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "clock.h"
#include "status.h"

typedef struct peer {
    int alive;       /* not lost */
    double heard;    /* when rank 0 last heard from it */
    int credit;      /* units it asked for and was not sent */
    int idle_sent;   /* told IDLE since it was last sent units */
    int bye, stopped;
} peer;

/* A message on its way to a worker: rank 0 never blocks in a send. Over
 * TCP a send to a rank that died can wait forever for its connection (seen
 * on the test cluster); the lease finds the rank lost meanwhile, and its
 * sends are left to MPI_Abort. */
typedef struct outgoing {
    MPI_Request req;
    void *buf;
} outgoing;

typedef struct server {
    rt_farm *f;
    const rt_farm_job *job;
    const rt_farm_rank0 *own;
    rt_root *R;
    rt_farm_result *res;
    peer *peers;
    void *buf; /* the message being received */
    size_t cap;
    uint32_t *out; /* UNITS being sent */
    size_t cap_out;
    double lease;
    double last_done;  /* when the last unit was reported done */
    double next_flush; /* when to ask for sums ahead of the next checkpoint */
    uint32_t pass_asked; /* passes whose sums were asked for */
    uint32_t frame_asked; /* a frame job: frames whose sums were asked for */
    int finishing;       /* FINISH sent */
    outgoing *outbox;    /* sends not yet complete */
    size_t n_outbox, cap_outbox;
} server;

/* Starts a send of count elements of size bytes to r (buf is copied);
 * MPI's status. */
static int post(server *s, int r, int tag, MPI_Datatype type, const void *buf, int count, size_t size)
{
    void *copy = count ? malloc((size_t)count * size) : NULL;
    if ((count && !copy) ||
        rt_array_reserve((void **)&s->outbox, &s->cap_outbox, s->n_outbox + 1, sizeof *s->outbox)) {
        free(copy);
        rt_farm_fail(s->f, RT_EXIT_RUNTIME, "out of memory on rank 0");
    }
    if (count)
        memcpy(copy, buf, (size_t)count * size);
    outgoing *o = &s->outbox[s->n_outbox];
    o->buf = copy;
    int rc = MPI_Isend(copy, count, type, r, tag, MPI_COMM_WORLD, &o->req);
    if (rc != MPI_SUCCESS) {
        free(copy);
        return rc;
    }
    s->n_outbox++;
    return MPI_SUCCESS;
}

/* Frees the sends that completed. */
static void reap(server *s)
{
    for (size_t i = 0; i < s->n_outbox;) {
        int done = 0;
        if (MPI_Test(&s->outbox[i].req, &done, MPI_STATUS_IGNORE) != MPI_SUCCESS)
            done = 0; /* an error: the lease decides about its rank */
        if (done) {
            free(s->outbox[i].buf);
            s->outbox[i] = s->outbox[--s->n_outbox];
        } else {
            i++;
        }
    }
}

static void lose(server *s, int r, const char *why);

/* Units for r, as many as it has credit for and there are. */
static void serve_peer(server *s, int r)
{
    peer *p = &s->peers[r];
    size_t n = 0;
    rt_unit u;
    while (p->alive && p->credit > 0 && rt_root_take(s->R, r, &u) > 0) {
        if (rt_array_reserve((void **)&s->out, &s->cap_out, (n + 1) * RT_MSG_UNIT, sizeof *s->out))
            rt_farm_fail(s->f, RT_EXIT_RUNTIME, "out of memory on rank 0");
        rt_msg_units_encode(s->out + n++ * RT_MSG_UNIT, &u, 1);
        p->credit--;
    }
    if (n) {
        p->idle_sent = 0;
        if (post(s, r, RT_TAG_UNITS, MPI_UINT32_T, s->out, (int)(n * RT_MSG_UNIT), sizeof *s->out) != MPI_SUCCESS)
            lose(s, r, "sending it units failed");
        return;
    }
    int none = rt_root_assigned(s->R, r) == 0;
    if (p->alive && none && !p->idle_sent && !s->finishing) {
        p->idle_sent = 1;
        if (post(s, r, RT_TAG_IDLE, MPI_BYTE, NULL, 0, 1) != MPI_SUCCESS)
            lose(s, r, "sending to it failed");
    }
}

static void serve_all(server *s)
{
    for (int r = 1; r < s->f->size; r++)
        if (s->peers[r].alive && s->peers[r].credit > 0)
            serve_peer(s, r);
}

/* r is lost: its units go back to the queue and to whoever asked. */
static void lose(server *s, int r, const char *why)
{
    if (!s->peers[r].alive)
        return;
    s->peers[r].alive = 0;
    s->res->lost++;
    const double now = rt_now();
    int complete;
    uint32_t back = rt_root_lose(s->R, r, now, s->peers[r].heard, &complete);
    fprintf(stderr, "rt-mpi: warning: rank %d lost (%s): %u unit%s go%s to the other ranks\n", r, why, back,
            back == 1 ? "" : "s", back == 1 ? "es" : "");
    int left = 0;
    for (int q = 1; q < s->f->size; q++)
        left += s->peers[q].alive;
    if (!left && s->job->root_serves_only && !complete)
        rt_farm_fail(s->f, RT_EXIT_RUNTIME, "every rank that renders is lost");
    serve_all(s);
}

/* Sums held by the workers, asked for (a pass is done, a checkpoint due). */
static void ask_sums(server *s)
{
    for (int r = 1; r < s->f->size; r++) {
        int held = rt_root_held(s->R, r) > 0;
        if (s->peers[r].alive && held && post(s, r, RT_TAG_FLUSH, MPI_BYTE, NULL, 0, 1) != MPI_SUCCESS)
            lose(s, r, "sending to it failed");
    }
}

static void on_report(server *s, int r, const int64_t *m, int count)
{
    size_t n;
    if (rt_msg_reports((size_t)count, &n))
        rt_farm_fail(s->f, RT_EXIT_RUNTIME, "malformed report from rank %d", r);
    for (size_t k = 0; k < n; k++) {
        const rt_msg_report rep = rt_msg_report_decode(m, k);
        if (rt_root_report(s->R, r, &rep))
            rt_farm_fail(s->f, RT_EXIT_RUNTIME, "rank %d reported unit %lld, which it does not hold", r,
                         (long long)m[k * RT_MSG_REPORT]);
    }
    s->last_done = rt_now();
    s->peers[r].credit += (int)n;
    serve_peer(s, r);
}

/* One piece at m (count int64 left): rows [y0, y1), columns [x0, x1),
 * samples [s0, s1), its units, their sums. Every unit must be one r holds,
 * of those rows and columns, and together they must cover exactly [s0,
 * s1). Returns the int64 it took. */
static size_t on_piece(server *s, int r, const int64_t *m, size_t count)
{
    rt_unit bounds;
    uint32_t max_ids;
    size_t ch;
    rt_root_bounds(s->R, &bounds, &max_ids, &ch);
    rt_msg_piece pc;
    /* any failure to decode is malformed; RT_EINVAL is only the ledger's */
    int st = rt_msg_piece_decode(m, count, &bounds, max_ids, ch, &pc) ? RT_EFORMAT : rt_root_sums(s->R, r, &pc);
    if (st == RT_EINVAL)
        rt_farm_fail(s->f, RT_EXIT_RUNTIME, "rank %d sent sums of a unit it does not hold", r);
    if (st)
        rt_farm_fail(s->f, RT_EXIT_RUNTIME, "malformed sums from rank %d", r);
    return pc.len;
}

/* A flush: one or more pieces. */
static void on_sums(server *s, int r, const int64_t *m, int count)
{
    for (size_t at = 0; at < (size_t)count;)
        at += on_piece(s, r, m + at, (size_t)count - at);
}

static void on_bye(server *s, int r, const double *m, int count)
{
    rt_msg_bye b;
    if (rt_msg_bye_decode(m, (size_t)count, &b))
        rt_farm_fail(s->f, RT_EXIT_RUNTIME, "malformed bye from rank %d", r);
    rt_root_bye(s->R, r, &b);
    s->peers[r].bye = 1;
}

/* The MPI type of the codec's elements. */
static MPI_Datatype mpi_type(rt_msg_elem e)
{
    switch (e) {
    case RT_MSG_I32:
        return MPI_INT32_T;
    case RT_MSG_U32:
        return MPI_UINT32_T;
    case RT_MSG_I64:
        return MPI_INT64_T;
    case RT_MSG_F64:
        return MPI_DOUBLE;
    default:
        return MPI_BYTE;
    }
}

/* Receives the message status announced and acts on it. */
static void receive(server *s, const MPI_Status *status)
{
    const int r = status->MPI_SOURCE, tag = status->MPI_TAG;
    size_t size;
    rt_msg_elem elem;
    if (rt_msg_kind(tag, &elem, &size))
        rt_farm_fail(s->f, RT_EXIT_RUNTIME, "unexpected message tag %d from rank %d", tag, r);
    MPI_Datatype type = mpi_type(elem);
    int count = 0;
    MPI_Get_count(status, type, &count);
    /* cap in bytes: messages of every type share the buffer */
    if (count < 0 || (count > 0 && rt_array_reserve(&s->buf, &s->cap, (size_t)count * size, 1)))
        rt_farm_fail(s->f, RT_EXIT_RUNTIME, "out of memory on rank 0");
    if (MPI_Recv(s->buf, count, type, r, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE) != MPI_SUCCESS) {
        lose(s, r, "receiving from it failed");
        return;
    }
    s->res->msgs_in++;
    s->res->bytes_in += (uint64_t)count * size;
    peer *p = &s->peers[r];
    if (!p->alive)
        return; /* a lost rank's word comes too late: its units are elsewhere */
    p->heard = rt_now();
    switch (tag) {
    case RT_TAG_HELLO: {
        int32_t want;
        p->credit = rt_msg_int_decode(s->buf, (size_t)count, &want) == RT_OK && want > 0 ? want : 1;
        serve_peer(s, r);
        break;
    }
    case RT_TAG_REPORT:
        on_report(s, r, s->buf, count);
        break;
    case RT_TAG_SUMS:
        on_sums(s, r, s->buf, count);
        break;
    case RT_TAG_BYE:
        on_bye(s, r, s->buf, count);
        break;
    case RT_TAG_STOPPED:
        p->stopped = 1;
        break;
    case RT_TAG_HOST: {
        char host[sizeof ((rt_rank_stats *)0)->host];
        if (rt_msg_host_decode(s->buf, (size_t)count, host, sizeof host))
            rt_farm_fail(s->f, RT_EXIT_RUNTIME, "malformed host name from rank %d", r);
        rt_root_host(s->R, r, host);
        break;
    }
    case RT_TAG_BEAT:
        break;
    default:
        rt_farm_fail(s->f, RT_EXIT_RUNTIME, "unexpected message tag %d from rank %d", tag, r);
    }
}

/* Takes in whatever came, or naps; returns 1 when a message came. */
static int poll_once(server *s, int *idle)
{
    int flag = 0;
    MPI_Status status;
    if (rt_inbox_probe(MPI_ANY_SOURCE, &flag, &status) != MPI_SUCCESS)
        rt_farm_fail(s->f, RT_EXIT_RUNTIME, "MPI_Iprobe failed");
    if (!flag) {
        rt_inbox_nap(idle);
        return 0;
    }
    *idle = 0;
    receive(s, &status);
    return 1;
}

/* Workers silent for longer than the lease are lost. */
static void check_leases(server *s)
{
    double now = rt_now();
    for (int r = 1; r < s->f->size; r++) {
        peer *p = &s->peers[r];
        if (p->alive && !p->bye && now - p->heard > s->lease) {
            char why[64];
            snprintf(why, sizeof why, "no word from it for %.1f s", now - p->heard);
            lose(s, r, why);
        }
    }
}

/* Whether every live worker has said BYE (bye) or at least STOPPED (!bye). */
static int live_peers_done(const server *s, int bye)
{
    for (int r = 1; r < s->f->size; r++)
        if (s->peers[r].alive && !(bye ? s->peers[r].bye : s->peers[r].stopped || s->peers[r].bye))
            return 0;
    return 1;
}

/* A signal stopped the job: every worker sends what it holds and stops
 * (mpirun forwards the signal to them; STOP covers a signal sent to rank
 * 0 alone). What is in is saved first: when a rank died, mpirun's SIGTERM
 * gives rank 0 about a second before it kills it, and the dead rank never
 * answers. Then it waits for the others a second at most (the caller saves
 * again). */
static void stop_workers(server *s)
{
    rt_root_save_now(s->R);
    for (int r = 1; r < s->f->size; r++)
        if (s->peers[r].alive && post(s, r, RT_TAG_STOP, MPI_BYTE, NULL, 0, 1) != MPI_SUCCESS)
            lose(s, r, "sending to it failed");
    double deadline = rt_now() + (s->lease < 1 ? s->lease : 1);
    int idle = 0;
    while (!live_peers_done(s, 0) && rt_now() < deadline)
        poll_once(s, &idle);
}

/* Progressive passes and checkpoints want the sums the workers hold. */
static void ask_when_due(server *s)
{
    const rt_farm_hooks *h = &s->own->hooks;
    int pass_done = rt_root_pass_done(s->R, s->pass_asked);
    double now = rt_now();
    int ckpt = h->save && now >= s->next_flush;
    if (ckpt)
        s->next_flush = now + h->save_interval;
    if (pass_done)
        s->pass_asked++;
    /* a frame job: every unit of a frame is done, its sums are wanted now
     * (the frame is written as soon as they are in) */
    int frame_done = 0;
    while (rt_root_frame_done(s->R, s->frame_asked)) {
        s->frame_asked++;
        frame_done = 1;
    }
    if (pass_done || ckpt || frame_done)
        ask_sums(s);
}

void rt_farm_serve(rt_farm *f, const rt_farm_job *job, const rt_farm_rank0 *own, rt_root *R,
                   rt_farm_result *res)
{
    server s;
    memset(&s, 0, sizeof s);
    s.f = f, s.job = job, s.own = own, s.R = R, s.res = res;
    s.peers = calloc((size_t)f->size, sizeof(peer));
    if (!s.peers)
        rt_farm_fail(f, RT_EXIT_RUNTIME, "out of memory on rank 0");
    s.lease = job->lease > 0 ? job->lease : RT_POLICY_LEASE;
    double cpu0 = rt_sysinfo_thread_cpu(), now = rt_now();
    s.next_flush = now + own->hooks.save_interval / 2;
    for (int r = 1; r < f->size; r++)
        s.peers[r] = (peer){.alive = 1, .heard = now};
    int idle = 0;
    for (;;) {
        if (RT_FARM_STOPPED()) {
            rt_root_wake(R); /* rank 0's render thread may be waiting: it leaves */
            stop_workers(&s); /* the caller saves and ends the job */
            break;
        }
        int complete;
        int err = rt_root_error(R, &complete);
        if (err)
            rt_farm_fail(f, RT_EXIT_RUNTIME, "rendering on rank 0 failed: %s", rt_status_str(err));
        if (rt_root_tick(R))
            serve_all(&s); /* a frame completed: units of a later one may be ready */
        ask_when_due(&s);
        if (complete && !s.finishing) {
            s.finishing = 1;
            res->final_combine = s.last_done > 0 ? rt_now() - s.last_done : 0;
            /* It tells the workers whether ranks were lost: then none may
             * wait for the others in MPI_Finalize (rt_farm_finalize). */
            for (int r = 1; r < f->size; r++) {
                int32_t lost = res->lost;
                if (s.peers[r].alive &&
                    post(&s, r, RT_TAG_FINISH, MPI_INT32_T, &lost, 1, sizeof lost) != MPI_SUCCESS)
                    lose(&s, r, "sending to it failed");
            }
        }
        if (complete && live_peers_done(&s, 1))
            break;
        check_leases(&s);
        reap(&s);
        poll_once(&s, &idle);
    }
    /* The sends to live ranks complete (they took their last message);
     * those to lost ranks are left to MPI_Abort (rt_farm_finalize). */
    reap(&s);
    for (size_t i = 0; i < s.n_outbox && !res->lost; i++)
        MPI_Wait(&s.outbox[i].req, MPI_STATUS_IGNORE);
    f->lost = res->lost;
    res->serve_cpu = rt_sysinfo_thread_cpu() - cpu0;
    if (!res->lost) {
        for (size_t i = 0; i < s.n_outbox; i++)
            free(s.outbox[i].buf);
        free(s.outbox);
    }
    free(s.peers);
    free(s.buf);
    free(s.out);
}
