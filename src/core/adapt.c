/* adapt.c - adaptive sampling's rule: how many samples a pixel takes from
 * its pilot's spread (render.h). A file of its own because the path loop
 * (path.h, inlined into dispatch.c and render.c) calls it: kept in render.c
 * it made render.c -> dispatch.c -> render.c a call cycle. */
#include "render.h"

uint32_t rt_render_adapt_count(double sum, double sum2, uint32_t n, double threshold, uint32_t samples)
{
    const double mean = sum / n, ref = mean > RT_ADAPT_FLOOR ? mean : RT_ADAPT_FLOOR;
    double var = (sum2 - sum * mean) / (double)(n - 1);
    var = var > 0.0 ? var : 0.0;
    /* the standard error of the mean of m samples is sqrt(var / m) */
    const double need = var / (threshold * ref * threshold * ref);
    uint32_t m = RT_ADAPT_FIRST;
    while (m < samples && (double)m < need)
        m *= 2;
    return m < samples ? m : samples;
}
