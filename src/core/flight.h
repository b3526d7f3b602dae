/* flight.h - a path segment through the scene's media: the spans of the
 * media the ray is inside up to the segment's end (a sphere's, or a hull's
 * from the world), and where in them the free flight scatters, if it does
 * (one optical depth -ln(u), densities adding where spans overlap). The
 * book-2 path loop's (path2.c); static inline, on its every segment in a
 * scene with media. */
#ifndef RT_FLIGHT_H
#define RT_FLIGHT_H

#include <math.h>
#include <stdint.h>

#include "detmath.h"
#include "path.h" /* T_MIN */
#include "sampler.h"
#include "scene.h"
#include "world.h"

/* Media spans a ray can be in at once, at most (rt_scene_add_medium_*
 * refuse more media than that). */
#define RT_FLIGHT_SPANS RT_SCENE_MAX_MEDIA

typedef struct rt_span {
    double a, b, density;
    uint32_t medium;
} rt_span;

/* A segment's media spans: their count, and when there are any the
 * length of the ray's direction and their whole optical depth. */
typedef struct rt_spans {
    rt_span sp[RT_FLIGHT_SPANS];
    uint32_t n;
    double len, whole;
} rt_spans;

/* The spans of the media ray is inside within (T_MIN, t_end). */
static inline __attribute__((always_inline)) void rt_flight_spans_of(const rt_scene *s, const rt_world *w,
                                                                     const rt_ray *ray, double t_end, rt_spans *S)
{
    const uint32_t n = s->media.media.n;
    rt_span *sp = S->sp;
    uint32_t ns = 0;
    for (uint32_t k = 0; k < n && ns < RT_FLIGHT_SPANS; k++) {
        const rt_medium *m = &s->media.media.items[k];
        double a, b;
        if (!(m->shape == RT_MEDIUM_SPHERE ? rt_world_sphere_span(m, ray, &a, &b)
                                            : rt_world_medium_span(w, k, ray, &a, &b)))
            continue;
        a = a > T_MIN ? a : T_MIN;
        b = b < t_end ? b : t_end;
        if (b > a)
            sp[ns++] = (rt_span){.a = a, .b = b, .density = m->density, .medium = k};
    }
    S->n = ns;
    if (!ns)
        return;
    S->len = rt_v3_len(ray->dir);
    S->whole = 0;
    for (uint32_t i = 0; i < ns; i++)
        S->whole += sp[i].density * (sp[i].b - sp[i].a) * S->len;
}

/* Where the optical depth tau is reached through the spans (a ray's
 * direction of length len), if it is: *t, and the spans live there (their
 * density's sum *dens, their count *live, the last of them *last).
 * Densities add where spans overlap. */
static inline __attribute__((always_inline)) int rt_flight_depth_reached(const rt_span *sp, uint32_t ns, double len, double tau,
                                                               double *t, double *dens, uint32_t *live,
                                                               uint32_t *last)
{
    double x = T_MIN, next;
    for (;;) { /* from x to the next span boundary; the spans live there */
        next = INFINITY, *dens = 0, *live = 0, *last = 0;
        for (uint32_t i = 0; i < ns; i++) {
            if (sp[i].a > x && sp[i].a < next)
                next = sp[i].a;
            if (sp[i].b > x && sp[i].b < next)
                next = sp[i].b;
            if (sp[i].a <= x && sp[i].b > x)
                *dens += sp[i].density, ++*live, *last = i;
        }
        if (next == INFINITY)
            return 0;
        const double depth = *dens * (next - x) * len;
        if (*dens > 0 && tau < depth) {
            *t = x + tau / (*dens * len);
            break;
        }
        tau -= depth;
        x = next;
    }
    /* The spans live at *t are those live at x when *t < next (x <= *t,
     * as x plus a quotient >= 0 rounds; no span starts or ends in (x,
     * next)), and their densities' sum in order is *dens; else (*t rounded
     * up to next) count them again. */
    if (!(*t < next)) {
        *dens = 0, *live = 0, *last = 0;
        for (uint32_t i = 0; i < ns; i++)
            if (sp[i].a <= *t && sp[i].b > *t)
                *dens += sp[i].density, ++*live, *last = i;
    }
    return 1;
}

/* Where in (T_MIN, t_end) the path scatters in the media, if it does:
 * one optical depth -ln(u) walked through the spans where the ray is inside
 * media (densities add where they overlap: the first of independent
 * exponential flights, as the book's media give when each draws its own),
 * then, where several overlap, which one in proportion to its density.
 * Its numbers come from smp, seeked to the bounce's flight dimension
 * (sampler.h). Returns 1 with *t and *medium. */
static inline int rt_flight_event(rt_sampler *smp, const rt_spans *S, double *t, uint32_t *medium)
{
    const rt_span *sp = S->sp;
    const uint32_t ns = S->n;
    if (!ns)
        return 0;
    const double len = S->len, whole = S->whole;
    const double u = rt_sampler_get1d(smp);
    /* No event when u passes the spans' whole optical depth: -ln(1 - u) >= u,
     * so the flight is longer than the depth too; a margin far above the
     * rounding of the depth's sum, of 1 - u and of rt_det_log keeps every
     * decision as the walk's. Most of book2-final's thin fog's segments end
     * here, without the logarithm. */
    if (u > whole * (1.0 + 1e-6) + 1e-12)
        return 0;
    const double tau = -rt_det_log(1.0 - u); /* (0, inf]: 1 - u is in (0, 1] */
    if (ns == 1) { /* one span (book2-final's fog): the walk below in one step, the same operations */
        if (!(sp[0].density > 0 && tau < whole))
            return 0;
        *t = sp[0].a + tau / (sp[0].density * len);
        *medium = sp[0].medium;
        return 1;
    }
    double dens;
    uint32_t live, last;
    if (!rt_flight_depth_reached(sp, ns, len, tau, t, &dens, &live, &last))
        return 0;
    /* Which medium: the first whose share of the density passes u. */
    *medium = sp[last].medium;
    if (live > 1) {
        double acc = 0;
        const double u = rt_sampler_get1d(smp) * dens;
        for (uint32_t i = 0; i < ns; i++)
            if (sp[i].a <= *t && sp[i].b > *t && (acc += sp[i].density) > u) {
                *medium = sp[i].medium;
                break;
            }
    }
    return 1;
}

#endif
