/* msg.c - the farm's wire: every message's encoder and decoder (msg.h). */
#include "msg.h"

#include <string.h>

#include "status.h"

int rt_msg_kind(int tag, rt_msg_elem *elem, size_t *size)
{
    switch (tag) {
    case RT_TAG_HELLO:
    case RT_TAG_FINISH:
        *elem = RT_MSG_I32, *size = 4;
        return RT_OK;
    case RT_TAG_UNITS:
        *elem = RT_MSG_U32, *size = 4;
        return RT_OK;
    case RT_TAG_REPORT:
    case RT_TAG_SUMS:
        *elem = RT_MSG_I64, *size = 8;
        return RT_OK;
    case RT_TAG_BYE:
        *elem = RT_MSG_F64, *size = 8;
        return RT_OK;
    case RT_TAG_HOST:
    case RT_TAG_BEAT:
    case RT_TAG_STOPPED:
    case RT_TAG_IDLE:
    case RT_TAG_FLUSH:
    case RT_TAG_STOP:
        *elem = RT_MSG_BYTES, *size = 1;
        return RT_OK;
    default:
        return RT_EFORMAT;
    }
}

/* The wire's order is id, rows, columns, samples. */
size_t rt_msg_units_encode(uint32_t *m, const rt_unit *u, size_t n)
{
    for (size_t k = 0; k < n; k++, m += RT_MSG_UNIT) {
        m[0] = u[k].id, m[1] = u[k].y0, m[2] = u[k].y1, m[3] = u[k].x0;
        m[4] = u[k].x1, m[5] = u[k].s0, m[6] = u[k].s1;
    }
    return n * RT_MSG_UNIT;
}

int rt_msg_units_decode(const uint32_t *m, size_t count, rt_unit *u, size_t cap, size_t *n)
{
    *n = 0;
    if (count == 0 || count % RT_MSG_UNIT || count / RT_MSG_UNIT > cap)
        return RT_EFORMAT;
    for (size_t k = 0; k < count / RT_MSG_UNIT; k++, m += RT_MSG_UNIT) {
        u[k].id = m[0], u[k].y0 = m[1], u[k].y1 = m[2], u[k].x0 = m[3];
        u[k].x1 = m[4], u[k].s0 = m[5], u[k].s1 = m[6];
    }
    *n = count / RT_MSG_UNIT;
    return RT_OK;
}

void rt_msg_report_encode(int64_t *m, const rt_msg_report *r)
{
    m[0] = r->id, m[1] = (int64_t)r->segs, m[2] = (int64_t)(r->start * 1e9), m[3] = (int64_t)(r->end * 1e9);
}

int rt_msg_reports(size_t count, size_t *n)
{
    *n = count / RT_MSG_REPORT;
    return count % RT_MSG_REPORT ? RT_EFORMAT : RT_OK;
}

rt_msg_report rt_msg_report_decode(const int64_t *m, size_t k)
{
    m += k * RT_MSG_REPORT;
    rt_msg_report r = {.id = m[0] >= 0 && m[0] <= UINT32_MAX ? (uint32_t)m[0] : UINT32_MAX,
                       .segs = (uint64_t)m[1],
                       .start = (double)m[2] * 1e-9,
                       .end = (double)m[3] * 1e-9};
    return r;
}

static size_t piece_sums(uint32_t y0, uint32_t y1, uint32_t x0, uint32_t x1, size_t ch)
{
    return (size_t)(y1 - y0) * (x1 - x0) * ch;
}

size_t rt_msg_piece_len(const rt_piece *p, size_t ch)
{
    return RT_MSG_PIECE + p->n_ids + piece_sums(p->y0, p->y1, p->x0, p->x1, ch);
}

int64_t *rt_msg_piece_encode(int64_t *m, const rt_piece *p, size_t ch)
{
    m[0] = p->y0, m[1] = p->y1, m[2] = p->x0, m[3] = p->x1, m[4] = p->s0, m[5] = p->s1;
    m[6] = (int64_t)p->n_ids;
    for (size_t k = 0; k < p->n_ids; k++)
        m[RT_MSG_PIECE + k] = p->ids[k];
    const size_t sums = piece_sums(p->y0, p->y1, p->x0, p->x1, ch);
    memcpy(m + RT_MSG_PIECE + p->n_ids, p->sums, sums * sizeof *p->sums);
    return m + RT_MSG_PIECE + p->n_ids + sums;
}

int rt_msg_piece_decode(const int64_t *m, size_t count, const rt_unit *bounds, uint32_t max_ids, size_t ch,
                        rt_msg_piece *out)
{
    memset(out, 0, sizeof *out);
    if (count < RT_MSG_PIECE)
        return RT_EFORMAT;
    if (!(m[6] > 0 && m[6] <= max_ids && m[0] >= bounds->y0 && m[0] < m[1] && m[1] <= bounds->y1 &&
          m[2] >= bounds->x0 && m[2] < m[3] && m[3] <= bounds->x1 && m[4] >= bounds->s0 && m[4] < m[5] &&
          m[5] <= bounds->s1))
        return RT_EFORMAT;
    const rt_unit b = {.y0 = (uint32_t)m[0],
                       .y1 = (uint32_t)m[1],
                       .x0 = (uint32_t)m[2],
                       .x1 = (uint32_t)m[3],
                       .s0 = (uint32_t)m[4],
                       .s1 = (uint32_t)m[5]};
    const size_t len = RT_MSG_PIECE + (size_t)m[6] + piece_sums(b.y0, b.y1, b.x0, b.x1, ch);
    if (count < len)
        return RT_EFORMAT;
    out->block = b;
    out->n_ids = (uint32_t)m[6];
    out->ids = m + RT_MSG_PIECE;
    out->sums = m + RT_MSG_PIECE + out->n_ids;
    out->len = len;
    return RT_OK;
}

int rt_msg_int_decode(const int32_t *m, size_t count, int32_t *v)
{
    if (count != 1)
        return RT_EFORMAT;
    *v = m[0];
    return RT_OK;
}

void rt_msg_bye_encode(double *m, const rt_msg_bye *b)
{
    m[0] = b->wait, m[1] = b->comm, m[2] = b->peak_mb, m[3] = b->held_mb;
}

int rt_msg_bye_decode(const double *m, size_t count, rt_msg_bye *b)
{
    if (count != RT_MSG_BYE)
        return RT_EFORMAT;
    b->wait = m[0], b->comm = m[1], b->peak_mb = m[2], b->held_mb = m[3];
    return RT_OK;
}

int rt_msg_host_decode(const char *m, size_t count, char *buf, size_t n)
{
    if (count > RT_MSG_HOST)
        return RT_EFORMAT;
    const size_t k = count < n ? count : n - 1;
    memcpy(buf, m, k);
    buf[k] = 0;
    return RT_OK;
}
