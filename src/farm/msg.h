/* msg.h - the farm's wire: the message tags, what each carries, and the one
 * encoder and decoder of each message. No MPI here: the server and the
 * worker move the arrays these functions fill and read (inbox.h polls).
 * Rank 0 hands out units and takes in small reports; the sums come
 * combined.
 *
 *   worker -> rank 0
 *     HOST     bytes: its host name (first, before HELLO)
 *     HELLO    int32: how many units it wants in flight
 *     REPORT   int64 x 4 per unit done: id, segments, start and end ns
 *              (worker clock since the common start); also its request
 *              for as many new units
 *     SUMS     int64, one or more pieces (held.h), each: y0, y1, x0, x1,
 *              s0, s1, n, n unit ids, then the sums of rows [y0, y1) and
 *              columns [x0, x1) over samples [s0, s1); each pixel at most
 *              once in a message
 *     BEAT     empty: alive, nothing else to say (a lease's worth of quiet)
 *     STOPPED  empty: stopped, every sum sent
 *     BYE      double x 4: wait s, comm s, peak MB, most MB held
 *   rank 0 -> worker
 *     UNITS    uint32 x 7 per unit: id, y0, y1, x0, x1, s0, s1
 *     IDLE     empty: no unit for you now: send what you hold
 *     FLUSH    empty: send what you hold (pass, checkpoint)
 *     STOP     empty: a signal stopped the job: send what you hold, stop
 *     FINISH   int32: every sum is in: say BYE and leave; how many ranks
 *              were lost (then nobody waits in MPI_Finalize)
 *
 * Decoders take the element count received and return a status: RT_EFORMAT
 * for a message that is truncated, too long or of an unknown tag; they never
 * read past count. No collective runs after the render starts: a lost rank
 * would hang it. */
#ifndef RT_FARM_MSG_H
#define RT_FARM_MSG_H

#include <stddef.h>
#include <stdint.h>

#include "held.h"

enum {
    RT_TAG_HELLO = 11,
    RT_TAG_REPORT,
    RT_TAG_SUMS,
    RT_TAG_BEAT,
    RT_TAG_STOPPED,
    RT_TAG_BYE,
    RT_TAG_UNITS,
    RT_TAG_IDLE,
    RT_TAG_FLUSH,
    RT_TAG_STOP,
    RT_TAG_FINISH,
    RT_TAG_HOST,
};
#define RT_MSG_REPORT 4 /* int64 per reported unit */
#define RT_MSG_UNIT 7   /* uint32 per unit sent */
#define RT_MSG_PIECE 7  /* int64 of a piece's header before its ids */
#define RT_MSG_BYE 4    /* double in a bye */
#define RT_MSG_HOST 256 /* most bytes of a host name */

/* What a tag's message is made of. */
typedef enum { RT_MSG_BYTES, RT_MSG_I32, RT_MSG_U32, RT_MSG_I64, RT_MSG_F64 } rt_msg_elem;

/* The element type of tag's messages and its size in bytes; RT_EFORMAT for
 * a tag that is not the farm's. */
int rt_msg_kind(int tag, rt_msg_elem *elem, size_t *size);

/* UNITS: n units into m (n * RT_MSG_UNIT); returns the count. */
size_t rt_msg_units_encode(uint32_t *m, const rt_unit *u, size_t n);
/* UNITS: at most cap units out of m (count uint32) into u, *n of them. */
int rt_msg_units_decode(const uint32_t *m, size_t count, rt_unit *u, size_t cap, size_t *n);

/* REPORT: one unit done. */
typedef struct rt_msg_report {
    uint32_t id; /* UINT32_MAX for an id that is no unit's */
    uint64_t segs;
    double start, end; /* s, worker clock */
} rt_msg_report;
void rt_msg_report_encode(int64_t *m, const rt_msg_report *r);
/* How many reports m holds (count int64). */
int rt_msg_reports(size_t count, size_t *n);
/* The k-th report of m (k below rt_msg_reports' n). */
rt_msg_report rt_msg_report_decode(const int64_t *m, size_t k);

/* SUMS: the int64 one piece of ch values a pixel takes. */
size_t rt_msg_piece_len(const rt_piece *p, size_t ch);
/* Writes p at m; returns the end of what it wrote. */
int64_t *rt_msg_piece_encode(int64_t *m, const rt_piece *p, size_t ch);
/* A piece read from the wire: its block (id 0), its unit ids and sums. */
typedef struct rt_msg_piece {
    rt_unit block;
    const int64_t *ids; /* n_ids, not checked against any schedule */
    uint32_t n_ids;
    const int64_t *sums; /* block's pixels * ch */
    size_t len;          /* int64 the piece takes */
} rt_msg_piece;
/* The piece at m (count int64 left) of an image width x height with
 * samples, at most max_ids ids: RT_EFORMAT if its header is out of those
 * bounds or it runs past count. */
int rt_msg_piece_decode(const int64_t *m, size_t count, const rt_unit *bounds, uint32_t max_ids, size_t ch,
                        rt_msg_piece *out);

/* HELLO and FINISH: one int32. */
int rt_msg_int_decode(const int32_t *m, size_t count, int32_t *v);

/* BYE: a worker's last numbers. */
typedef struct rt_msg_bye {
    double wait, comm, peak_mb, held_mb;
} rt_msg_bye;
void rt_msg_bye_encode(double *m, const rt_msg_bye *b);
int rt_msg_bye_decode(const double *m, size_t count, rt_msg_bye *b);

/* HOST: a name of count bytes (no terminator) into buf of n bytes, cut to
 * fit and terminated; RT_EFORMAT when longer than RT_MSG_HOST. */
int rt_msg_host_decode(const char *m, size_t count, char *buf, size_t n);

#endif
