/* units.c - running a rank's units, on rank 0 and on workers alike:
 * rendered (rt_render_stream), or the empty units of the farm benchmark;
 * and the per-unit time accounting both share. */
#include "internal.h"

#include <stdlib.h>

#include "status.h"

int rt_farm_run_units(const rt_farm_job *job, const rt_render_source *src)
{
    if (!job->empty_units)
        return rt_render_stream(job->renderer, job->threads, src);
    /* --empty-units: every unit adds nothing, without rendering; the zero
     * sums come from one buffer that grows to the largest unit. */
    const size_t ch = job->renderer->lay.ch;
    int64_t *zero = NULL;
    size_t cap = 0;
    int st = RT_OK, got;
    rt_unit u;
    while (!RT_FARM_STOPPED() && (got = src->take(src->ctx, &u)) != 0) {
        if (got > 0) {
            size_t n = (size_t)rt_unit_pixels(&u) * ch;
            if (n > cap) {
                free(zero);
                cap = 0;
                if (!(zero = calloc(n, sizeof *zero))) {
                    st = RT_ENOMEM;
                    break;
                }
                cap = n;
            }
            src->done(src->ctx, &u, zero, 0);
        }
        if (src->poll)
            src->poll(src->ctx, got < 0);
    }
    free(zero);
    return st;
}

double rt_farm_unit_start(double taken, double *last, double end)
{
    double start = taken > *last ? taken : *last;
    *last = end;
    return start;
}
