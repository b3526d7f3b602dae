/* test_msg.c - the farm's wire (msg.h): every message comes back as it was
 * sent; a truncated, oversized or unknown message is refused with a status
 * and never read past its end (each decode gets exactly the count it may
 * read, from a heap block of that size, so ASan would see a read past it). */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "msg.h"
#include "status.h"

static void *copy(const void *src, size_t bytes)
{
    void *p = malloc(bytes ? bytes : 1);
    memcpy(p, src, bytes);
    return p;
}

static void test_units(void)
{
    const rt_unit u[2] = {{3, 10, 12, 0, 8, 0, 64}, {4, 0, 16, 8, 16, 16, 32}};
    uint32_t m[2 * RT_MSG_UNIT];
    CHECK_EQ_INT(rt_msg_units_encode(m, u, 2), 2 * RT_MSG_UNIT);
    CHECK_EQ_INT(m[4], 64); /* the wire: id, rows, columns, samples */
    CHECK_EQ_INT(m[6], 8);
    rt_unit back[2];
    size_t n = 9;
    CHECK_EQ_INT(rt_msg_units_decode(m, 2 * RT_MSG_UNIT, back, 2, &n), RT_OK);
    CHECK_EQ_INT(n, 2);
    CHECK_EQ_INT(memcmp(back, u, sizeof u), 0);
    CHECK_EQ_INT(rt_msg_units_decode(m, 2 * RT_MSG_UNIT - 1, back, 2, &n), RT_EFORMAT); /* truncated */
    CHECK_EQ_INT(rt_msg_units_decode(m, 2 * RT_MSG_UNIT, back, 1, &n), RT_EFORMAT);     /* more than asked */
    CHECK_EQ_INT(rt_msg_units_decode(m, 0, back, 2, &n), RT_EFORMAT);                  /* empty */
    CHECK_EQ_INT(n, 0);
}

static void test_report(void)
{
    const rt_msg_report r[2] = {{7, 123456789012ULL, 1.5, 2.25}, {UINT32_MAX - 1, 0, 0, 3e-9}};
    int64_t m[2 * RT_MSG_REPORT];
    rt_msg_report_encode(m, &r[0]);
    rt_msg_report_encode(m + RT_MSG_REPORT, &r[1]);
    size_t n = 0;
    CHECK_EQ_INT(rt_msg_reports(2 * RT_MSG_REPORT, &n), RT_OK);
    CHECK_EQ_INT(n, 2);
    for (size_t k = 0; k < n; k++) {
        rt_msg_report b = rt_msg_report_decode(m, k);
        CHECK_EQ_INT(b.id, r[k].id);
        CHECK_EQ_U64(b.segs, r[k].segs);
        CHECK_NEAR(b.start, r[k].start, 1e-9);
        CHECK_NEAR(b.end, r[k].end, 1e-9);
    }
    CHECK_EQ_INT(rt_msg_reports(2 * RT_MSG_REPORT + 1, &n), RT_EFORMAT);
    m[0] = -1; /* no unit's id */
    CHECK_EQ_INT(rt_msg_report_decode(m, 0).id, UINT32_MAX);
}

/* Two pieces of 2 channels in one SUMS message, decoded back in turn. */
static void test_sums(void)
{
    int64_t s1[2 * 3 * 2], s2[1 * 4 * 2];
    for (size_t i = 0; i < 12; i++)
        s1[i] = (int64_t)i * 1000003 - 5;
    for (size_t i = 0; i < 8; i++)
        s2[i] = -(int64_t)i;
    uint32_t ids1[2] = {5, 6}, ids2[1] = {9};
    rt_piece p[2] = {{.y0 = 4, .y1 = 6, .s0 = 0, .s1 = 8, .x0 = 1, .x1 = 4, .sums = s1, .ids = ids1, .n_ids = 2},
                     {.y0 = 7, .y1 = 8, .s0 = 8, .s1 = 16, .x0 = 0, .x1 = 4, .sums = s2, .ids = ids2, .n_ids = 1}};
    const size_t len = rt_msg_piece_len(&p[0], 2) + rt_msg_piece_len(&p[1], 2);
    CHECK_EQ_INT(len, RT_MSG_PIECE + 2 + 12 + RT_MSG_PIECE + 1 + 8);
    int64_t *wire = malloc(len * sizeof *wire);
    int64_t *end = rt_msg_piece_encode(rt_msg_piece_encode(wire, &p[0], 2), &p[1], 2);
    CHECK_EQ_INT(end - wire, len);
    const rt_unit bounds = {.y1 = 8, .s1 = 16, .x1 = 4};
    size_t at = 0;
    for (int i = 0; i < 2; i++) {
        rt_msg_piece pc;
        CHECK_EQ_INT(rt_msg_piece_decode(wire + at, len - at, &bounds, 10, 2, &pc), RT_OK);
        CHECK_EQ_INT(pc.len, rt_msg_piece_len(&p[i], 2));
        CHECK_EQ_INT(pc.block.y0, p[i].y0);
        CHECK_EQ_INT(pc.block.y1, p[i].y1);
        CHECK_EQ_INT(pc.block.x0, p[i].x0);
        CHECK_EQ_INT(pc.block.x1, p[i].x1);
        CHECK_EQ_INT(pc.block.s0, p[i].s0);
        CHECK_EQ_INT(pc.block.s1, p[i].s1);
        CHECK_EQ_INT(pc.n_ids, p[i].n_ids);
        CHECK_EQ_INT(pc.ids[0], p[i].ids[0]);
        CHECK_EQ_INT(memcmp(pc.sums, p[i].sums, (pc.len - RT_MSG_PIECE - pc.n_ids) * sizeof *pc.sums), 0);
        at += pc.len;
    }
    CHECK_EQ_INT(at, len);
    /* truncated anywhere in the first piece: refused, from a block that
     * ends where the count says */
    const size_t first = rt_msg_piece_len(&p[0], 2);
    for (size_t cut = 0; cut < first; cut++) {
        int64_t *t = copy(wire, cut * sizeof *wire);
        rt_msg_piece pc;
        CHECK_EQ_INT(rt_msg_piece_decode(t, cut, &bounds, 10, 2, &pc), RT_EFORMAT);
        free(t);
    }
    /* out of the image, of the samples, with no or too many ids */
    const int64_t bad[][RT_MSG_PIECE] = {{4, 9, 1, 4, 0, 8, 2}, {4, 6, 1, 5, 0, 8, 2}, {4, 6, 1, 4, 8, 17, 2},
                                         {6, 6, 1, 4, 0, 8, 2}, {4, 6, 1, 4, 0, 8, 0}, {4, 6, 1, 4, 0, 8, 11},
                                         {-1, 6, 1, 4, 0, 8, 2}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        memcpy(wire, bad[i], sizeof bad[i]);
        rt_msg_piece pc;
        CHECK_EQ_INT(rt_msg_piece_decode(wire, len, &bounds, 10, 2, &pc), RT_EFORMAT);
    }
    free(wire);
}

static void test_small(void)
{
    int32_t v = 0, two[2] = {3, 4};
    CHECK_EQ_INT(rt_msg_int_decode(two, 1, &v), RT_OK);
    CHECK_EQ_INT(v, 3);
    CHECK_EQ_INT(rt_msg_int_decode(two, 2, &v), RT_EFORMAT);
    CHECK_EQ_INT(rt_msg_int_decode(two, 0, &v), RT_EFORMAT);

    const rt_msg_bye b = {.wait = 1.25, .comm = 0.5, .peak_mb = 812.0, .held_mb = 64.5};
    double m[RT_MSG_BYE + 1] = {0};
    rt_msg_bye_encode(m, &b);
    rt_msg_bye back;
    CHECK_EQ_INT(rt_msg_bye_decode(m, RT_MSG_BYE, &back), RT_OK);
    CHECK_EQ_INT(memcmp(&back, &b, sizeof b), 0);
    CHECK_EQ_INT(rt_msg_bye_decode(m, RT_MSG_BYE - 1, &back), RT_EFORMAT);
    CHECK_EQ_INT(rt_msg_bye_decode(m, RT_MSG_BYE + 1, &back), RT_EFORMAT);

    char host[8];
    CHECK_EQ_INT(rt_msg_host_decode("node-17", 7, host, sizeof host), RT_OK);
    CHECK_EQ_INT(strcmp(host, "node-17"), 0);
    CHECK_EQ_INT(rt_msg_host_decode("node-1234", 9, host, sizeof host), RT_OK); /* cut to fit */
    CHECK_EQ_INT(strcmp(host, "node-12"), 0);
    char *big = calloc(RT_MSG_HOST + 1, 1);
    CHECK_EQ_INT(rt_msg_host_decode(big, RT_MSG_HOST + 1, host, sizeof host), RT_EFORMAT);
    free(big);

    rt_msg_elem e;
    size_t size = 0;
    CHECK_EQ_INT(rt_msg_kind(RT_TAG_SUMS, &e, &size), RT_OK);
    CHECK_EQ_INT(e, RT_MSG_I64);
    CHECK_EQ_INT(size, 8);
    CHECK_EQ_INT(rt_msg_kind(RT_TAG_HOST, &e, &size), RT_OK);
    CHECK_EQ_INT(e, RT_MSG_BYTES);
    CHECK_EQ_INT(rt_msg_kind(RT_TAG_HELLO - 1, &e, &size), RT_EFORMAT); /* unknown */
    CHECK_EQ_INT(rt_msg_kind(RT_TAG_HOST + 1, &e, &size), RT_EFORMAT);
}

int main(void)
{
    test_units();
    test_report();
    test_sums();
    test_small();
    CHECK_DONE();
}
