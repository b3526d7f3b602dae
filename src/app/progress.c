/* progress.c - stderr progress reporting for rank 0. */
#define _POSIX_C_SOURCE 200809L
#include "clock.h"
#include "progress.h"

#include <stdio.h>
#include <time.h>
#include <unistd.h>

void rt_progress_init(rt_progress *p, uint64_t total_rows, int quiet)
{
    p->enabled = !quiet;
    p->tty = isatty(STDERR_FILENO);
    p->t0 = rt_now();
    p->last = p->t0;
    p->total_rows = total_rows ? total_rows : 1;
    p->pass = p->passes = 0;
    p->base_rows = 0;
    p->offset_rows = p->offset_segments = 0;
    p->frame_rows = p->total_rows;
    p->frame_index = p->frames = 0;
}

static void fmt_time(char *buf, size_t n, double s)
{
    if (s < 0 || s > 1e7) {
        snprintf(buf, n, "--:--");
        return;
    }
    long t = (long)(s + 0.5);
    if (t >= 3600)
        snprintf(buf, n, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
    else
        snprintf(buf, n, "%ld:%02ld", t / 60, t % 60);
}

static void print_line(rt_progress *p, uint64_t rows_done, uint64_t segments, double now, int final)
{
    double el = now - p->t0, frac = (double)rows_done / (double)p->total_rows;
    double todo = (double)(p->total_rows - p->base_rows);
    double new_frac = todo > 0 ? (double)(rows_done - p->base_rows) / todo : 1.0;
    double eta = new_frac > 0 ? el * (1.0 - new_frac) / new_frac : -1;
    char e[32], r[32];
    fmt_time(e, sizeof e, el);
    fmt_time(r, sizeof r, eta);
    char passbuf[48] = "";
    if (p->passes > 1)
        snprintf(passbuf, sizeof passbuf, "pass %d/%d ", p->pass, p->passes);
    else if (p->frames)
        snprintf(passbuf, sizeof passbuf, "frame %u/%u ", p->frame_index + 1, p->frames);
    fprintf(stderr, "%s%srows %llu/%llu (%5.1f%%)  elapsed %s  eta %s  %.2f Mrays/s%s", p->tty ? "\r" : "",
            passbuf, (unsigned long long)rows_done, (unsigned long long)p->total_rows, 100.0 * frac, e, r,
            el > 0 ? (double)segments / el / 1e6 : 0.0, p->tty ? (final ? "\n" : "\033[K") : "\n");
    fflush(stderr);
}

void rt_progress_update(rt_progress *p, uint64_t rows_done, uint64_t segments)
{
    if (!p->enabled)
        return;
    double now = rt_now();
    double interval = p->tty ? 0.25 : 10.0;
    if (now - p->last < interval)
        return;
    p->last = now;
    print_line(p, p->offset_rows + rows_done, p->offset_segments + segments, now, 0);
}

void rt_progress_finish(rt_progress *p, uint64_t segments)
{
    if (!p->enabled)
        return;
    print_line(p, p->offset_rows + p->frame_rows, p->offset_segments + segments, rt_now(), 1);
}
