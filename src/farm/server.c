/* server.c - rank 0's main thread under MPI: hands out units on request
 * and takes in results, calling the hooks in between. It never blocks in
 * MPI (Open MPI busy-polls inside blocking calls): it probes and sleeps with
 * a short back-off, so it costs next to no CPU while rank 0's render thread
 * works. Each result is also the worker's request for one more unit, so a
 * worker always has the next unit at hand and a slow rank gets fewer. */
#include "msg.h"

#include <stdlib.h>

#include "status.h"

typedef struct server {
    const rt_farm *f;
    rt_root *R;
    int *outstanding; /* per rank: units sent and not yet returned */
    int finished;     /* workers told DONE */
    int64_t *msg;     /* the last result received */
    size_t cap;
} server;

/* A worker wants `want` units in flight (its first message). */
static void on_hello(server *s, int src)
{
    int32_t want = 0;
    MPI_Recv(&want, 1, MPI_INT32_T, src, RT_TAG_HELLO, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    rt_unit u;
    for (int k = 0; k < want && rt_root_take(s->R, &u); k++) {
        rt_msg_send_unit(s->f, src, &u);
        s->outstanding[src]++;
    }
    if (s->outstanding[src] == 0) {
        rt_msg_send_done(s->f, src);
        s->finished++;
    }
}

/* A result: checked, added, and answered with the next unit (or DONE once
 * the worker has none left in flight). */
static void on_result(server *s, int src, const MPI_Status *status)
{
    const rt_farm *f = s->f;
    int count = 0;
    MPI_Get_count(status, MPI_INT64_T, &count);
    if (count < RT_MSG_HDR)
        rt_farm_fail(f, 1, "malformed result from rank %d", src);
    if ((size_t)count > s->cap) {
        int64_t *q = realloc(s->msg, (size_t)count * sizeof *q);
        if (!q)
            rt_farm_fail(f, 1, "out of memory on rank 0");
        s->msg = q;
        s->cap = (size_t)count;
    }
    if (MPI_Recv(s->msg, count, MPI_INT64_T, src, RT_TAG_RESULT, MPI_COMM_WORLD, MPI_STATUS_IGNORE) != MPI_SUCCESS)
        rt_farm_fail(f, 1, "receiving a result from rank %d failed", src);
    const int64_t *m = s->msg;
    pthread_mutex_lock(&s->R->mu);
    const rt_unit *known = m[0] >= 0 && m[0] <= UINT32_MAX ? rt_sched_unit(&s->R->as.sched, (uint32_t)m[0]) : NULL;
    rt_unit done = known ? *known : (rt_unit){0, 0, 0, 0, 0};
    pthread_mutex_unlock(&s->R->mu);
    if (!known)
        rt_farm_fail(f, 1, "result for unknown unit %lld from rank %d", (long long)m[0], src);
    if ((size_t)count != RT_MSG_HDR + (size_t)(done.y1 - done.y0) * s->R->as.width * 3)
        rt_farm_fail(f, 1, "result of wrong size from rank %d", src);
    rt_root_add(s->R, src, &done, m + RT_MSG_HDR, (uint64_t)m[1], (double)m[2] * 1e-9, (double)m[3] * 1e-9);
    rt_unit next;
    if (rt_root_take(s->R, &next)) {
        rt_msg_send_unit(f, src, &next);
    } else if (--s->outstanding[src] == 0) {
        rt_msg_send_done(f, src);
        s->finished++;
    }
}

void rt_farm_serve(const rt_farm *f, rt_root *R)
{
    server s = {f, R, calloc((size_t)f->size, sizeof(int)), 0, NULL, 0};
    if (!s.outstanding)
        rt_farm_fail(f, 1, "out of memory on rank 0");
    int idle = 0;
    while (!RT_FARM_STOPPED()) { /* on a signal the caller saves and ends the job */
        pthread_mutex_lock(&R->mu);
        int complete = rt_assembly_complete(&R->as), err = R->error;
        pthread_mutex_unlock(&R->mu);
        if (err)
            rt_farm_fail(f, 1, "rendering on rank 0 failed: %s", rt_status_str(err));
        rt_root_tick(R);
        if (complete && s.finished == f->size - 1)
            break;
        int flag = 0;
        MPI_Status status;
        if (rt_msg_probe(MPI_ANY_SOURCE, &flag, &status) != MPI_SUCCESS)
            rt_farm_fail(f, 1, "MPI_Iprobe failed");
        if (!flag) {
            rt_msg_nap(&idle);
            continue;
        }
        idle = 0;
        if (status.MPI_TAG == RT_TAG_HELLO)
            on_hello(&s, status.MPI_SOURCE);
        else if (status.MPI_TAG == RT_TAG_RESULT)
            on_result(&s, status.MPI_SOURCE, &status);
        else
            rt_farm_fail(f, 1, "unexpected message tag %d from rank %d", status.MPI_TAG, status.MPI_SOURCE);
    }
    free(s.outstanding);
    free(s.msg);
}
