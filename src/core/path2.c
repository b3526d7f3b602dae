/* path2.c - the book-2 path loop: the scenes of "The Next Week" (quads,
 * moving spheres, textures, emitters, constant media, a background colour,
 * the books' camera), for scenes with such content only (rt_scene_is_book2);
 * book 1's scenes keep path.h's loops, their bytes and their speed. It
 * shares path.h's pixel sums, roulette, adaptive rule and buffers, and
 * draws its numbers by sampler.h's book-2 layout. In scenes with emitters
 * it samples them at diffuse vertices (nee.h), unless the job says not. */
#include "path2.h"

#include "detmath.h"
#include "nee.h"
#include "path.h"
#include "texture.h"
#include "world.h"

/* Media spans a ray can be in at once, at most (rt_scene_add_medium_*
 * refuse more media than that). */
#define SPANS RT_SCENE_MAX_MEDIA

typedef struct p2 {
    const rt_renderer *r;
    const rt_world *w;
    const rt_scene *s;
    const rt_perlin *pn; /* the world's noise tables */
    pixel_ctx pc;
    uint32_t stride; /* sampler dimensions per bounce (sampler.h) */
    int cosine;      /* lambertian surfaces scatter by material.c's cosine rule (no lights to sample) */
} p2;

/* The vertex a path is at: the bounce's depth and first dimension, the
 * path's time, the BSDF density of the ray that left the vertex before
 * (0: specular, or the camera's), and the segment count. */
typedef struct vertex {
    uint32_t depth, base;
    double time, pdf;
    uint64_t *segs;
} vertex;

/* A new path for sample `sample`: its camera ray and its time. */
static void start2(const p2 *c, uint32_t sample, path *p, double *time)
{
    const rt_renderer *r = c->r;
    const uint32_t W = r->job.width, H = r->job.height;
    p->smp = rt_sampler_start(&c->pc.smp, sample);
    p->thr = rt_v3(1, 1, 1);
    p->col = rt_v3(0, 0, 0);
    p->aov = (aov_rec){0, {0, 0, 0}, {0, 0, 0}};
    double du, dv, u, v;
    rt_sampler_pixel2d(&p->smp, &du, &dv);
    if (c->s->camera.pixels == RT_PIXELS_BOOK2) { /* pixel centres, jitter in [-0.5, 0.5) */
        u = ((double)c->pc.x + du) / (double)W;
        v = 1.0 - ((double)c->pc.y + dv) / (double)H;
    } else {
        u = ((double)c->pc.x + du) / (double)(W > 1 ? W - 1 : 1);
        v = ((double)(H - 1 - c->pc.y) + dv) / (double)(H > 1 ? H - 1 : 1);
    }
    rt_vec3 d = {0, 0, 0};
    if (r->camera.lens_radius > 0.0)
        d = rt_sampler_lens(&p->smp);
    p->ray = rt_camera_ray_lens(&r->camera, u, v, d.x, d.y);
    rt_sampler_seek(&p->smp, RT_SAMPLER2_DIM_TIME);
    *time = r->time0 + rt_sampler_get1d(&p->smp) * (r->time1 - r->time0); /* [0, 1): u itself */
}

typedef struct span {
    double a, b, density;
    uint32_t medium;
} span;

/* Where in (T_MIN, t_end) the path scatters in the media, if it does:
 * one optical depth -ln(u) walked through the spans where the ray is inside
 * media (densities add where they overlap: the first of independent
 * exponential flights, as the book's media give when each draws its own),
 * then, where several overlap, which one in proportion to its density.
 * Returns 1 with *t and *medium. */
static int medium_event(const p2 *c, path *p, double t_end, double *t, uint32_t *medium)
{
    const uint32_t n = c->s->media.media.n;
    span sp[SPANS];
    uint32_t ns = 0;
    for (uint32_t k = 0; k < n && ns < SPANS; k++) {
        const rt_medium *m = &c->s->media.media.items[k];
        double a, b;
        if (!(m->shape == RT_MEDIUM_SPHERE ? rt_world_sphere_span(m, &p->ray, &a, &b)
                                            : rt_world_medium_span(c->w, k, &p->ray, &a, &b)))
            continue;
        a = a > T_MIN ? a : T_MIN;
        b = b < t_end ? b : t_end;
        if (b > a)
            sp[ns++] = (span){.a = a, .b = b, .density = m->density, .medium = k};
    }
    if (!ns)
        return 0;
    const double len = rt_v3_len(p->ray.dir);
    const double u = rt_sampler_get1d(&p->smp);
    /* No event when u passes the spans' whole optical depth: -ln(1 - u) >= u,
     * so the flight is longer than the depth too; a margin far above the
     * rounding of the depth's sum, of 1 - u and of rt_det_log keeps every
     * decision as the walk's. Most of book2-final's thin fog's segments end
     * here, without the logarithm. */
    double whole = 0;
    for (uint32_t i = 0; i < ns; i++)
        whole += sp[i].density * (sp[i].b - sp[i].a) * len;
    if (u > whole * (1.0 + 1e-6) + 1e-12)
        return 0;
    double tau = -rt_det_log(1.0 - u); /* (0, inf]: 1 - u is in (0, 1] */
    if (ns == 1) { /* one span (book2-final's fog): the walk below in one step, the same operations */
        const double depth = sp[0].density * (sp[0].b - sp[0].a) * len;
        if (!(sp[0].density > 0 && tau < depth))
            return 0;
        *t = sp[0].a + tau / (sp[0].density * len);
        *medium = sp[0].medium;
        return 1;
    }
    double x = T_MIN, next, dens;
    uint32_t live, last;
    for (;;) { /* from x to the next span boundary; the spans live there */
        next = INFINITY, dens = 0, live = 0, last = 0;
        for (uint32_t i = 0; i < ns; i++) {
            if (sp[i].a > x && sp[i].a < next)
                next = sp[i].a;
            if (sp[i].b > x && sp[i].b < next)
                next = sp[i].b;
            if (sp[i].a <= x && sp[i].b > x)
                dens += sp[i].density, live++, last = i;
        }
        if (next == INFINITY)
            return 0;
        const double depth = dens * (next - x) * len;
        if (dens > 0 && tau < depth) {
            *t = x + tau / (dens * len);
            break;
        }
        tau -= depth;
        x = next;
    }
    /* Which medium: the first whose share of the density passes u. The
     * spans live at *t are those live at x when *t < next (x <= *t, as x
     * plus a quotient >= 0 rounds; no span starts or ends in (x, next)),
     * and their densities' sum in order is dens; else (*t rounded up to
     * next) count them again. */
    if (!(*t < next)) {
        dens = 0, live = 0, last = 0;
        for (uint32_t i = 0; i < ns; i++)
            if (sp[i].a <= *t && sp[i].b > *t)
                dens += sp[i].density, live++, last = i;
    }
    *medium = sp[last].medium;
    if (live > 1) {
        double acc = 0;
        const double u = rt_sampler_get1d(&p->smp) * dens;
        for (uint32_t i = 0; i < ns; i++)
            if (sp[i].a <= *t && sp[i].b > *t && (acc += sp[i].density) > u) {
                *medium = sp[i].medium;
                break;
            }
    }
    return 1;
}

static rt_vec3 clamp3(rt_vec3 v) { return rt_v3(clamp01(v.x), clamp01(v.y), clamp01(v.z)); }

/* The background's light for a path that leaves the scene. */
static void miss2(const p2 *c, path *p)
{
    rt_vec3 bg = c->s->background;
    if (c->s->background_kind == RT_BACKGROUND_SKY) {
        const double t = 0.5 * (rt_v3_unit(p->ray.dir).y + 1.0);
        bg = rt_v3_add(rt_v3_scale(c->s->sky_bottom, 1.0 - t), rt_v3_scale(c->s->sky_top, t));
    }
    p->col = rt_v3_add(p->col, rt_v3_mul(p->thr, bg));
    if (c->pc.aovs && !p->aov.done)
        p->aov = (aov_rec){1, clamp3(bg), rt_v3(0, 0, 0)};
}

#define PI 3.14159265358979323846

/* The light a diffuse vertex at `at` (normal n, zero for isotropic) of
 * albedo gets from a light it samples; called when there are lights to
 * sample and the next segment is within the depth limit (as the emitter a
 * scattered ray could hit). Its numbers: the bounce's light dimensions;
 * the scattering's follow. Inline: a wrapper of its own out of line cost a
 * second call a vertex (nee.c's work stays out of the loop). */
static int lit(const p2 *c, const vertex *v) { return c->r->lights && v->depth + 1 < c->r->job.max_depth; }

static inline void direct2(const p2 *c, path *p, const vertex *v, rt_vec3 at, rt_vec3 n, rt_vec3 albedo)
{
    rt_sampler_seek(&p->smp, v->base + RT_SAMPLER2_LIGHT);
    p->col = rt_v3_add(p->col, rt_nee_direct(c->r, at, n, rt_v3_mul(p->thr, albedo), v->time, &p->smp, v->segs));
    rt_sampler_seek(&p->smp, v->base + RT_SAMPLER2_SCATTER);
}

/* Scattering in medium k at distance t: the phase function's direction
 * (isotropic), the medium's colour. */
static void scatter_medium(const p2 *c, path *p, vertex *v, uint32_t k, double t)
{
    const rt_material *m = &c->s->materials[c->s->media.media.items[k].material];
    const rt_vec3 at = rt_ray_at(&p->ray, t);
    const rt_vec3 albedo = rt_texture_albedo(c->s, rt_world_perlin(c->w), m, 0, 0, at);
    if (c->pc.aovs && !p->aov.done)
        p->aov = (aov_rec){1, clamp3(albedo), rt_v3(0, 0, 0)};
    if (lit(c, v))
        direct2(c, p, v, at, rt_v3(0, 0, 0), albedo);
    p->thr = rt_v3_mul(p->thr, albedo);
    p->ray.orig = at;
    p->ray.dir = rt_warp_sphere(rt_sampler_get2d(&p->smp));
    v->pdf = 1.0 / (4.0 * PI);
}

/* A surface hit: its emission, or its scattering. Returns 1 when the path
 * goes on. */
static int surface2(const p2 *c, path *p, const rt_whit *h, vertex *vx)
{
    const double time = vx->time;
    const rt_material *m = &c->s->materials[h->material];
    rt_surface rec;
    double u, v;
    rt_world_surface(c->w, h, &p->ray, time, m->texture != 0, &rec, &u, &v);
    const rt_vec3 col = rt_texture_albedo(c->s, c->pn, m, u, v, rec.p);
    if (m->kind == RT_MAT_EMITTER) {
        if (rec.front_face || (m->flags & RT_MAT_TWO_SIDED)) {
            const double w = c->r->lights ? rt_nee_weight(c->r, &p->ray, vx->pdf, h, time) : 1.0;
            p->col = rt_v3_add(p->col, rt_v3_scale(rt_v3_mul(p->thr, col), w));
        }
        /* the denoiser's albedo of a light: its emission clamped to [0, 1] */
        if (c->pc.aovs && !p->aov.done)
            p->aov = (aov_rec){1, clamp3(col), rec.normal};
        return 0;
    }
    if (c->pc.aovs && !p->aov.done) {
        const int specular = m->kind == RT_MAT_DIELECTRIC || (m->kind == RT_MAT_METAL && m->fuzz == 0.0);
        p->aov = (aov_rec){!specular, m->kind == RT_MAT_DIELECTRIC ? rt_v3(1, 1, 1) : col, rec.normal};
    }
    vx->pdf = 0.0;
    if (m->kind == RT_MAT_LAMBERTIAN && c->cosine) { /* rt_material_scatter's lambertian, its operations inline */
        p->thr = rt_v3_mul(p->thr, col);
        p->ray = (rt_ray){rec.p, rt_warp_lambert(rt_sampler_get2d(&p->smp), rec.normal)};
        return 1;
    }
    rt_vec3 att;
    rt_ray next;
    if (m->kind == RT_MAT_ISOTROPIC) { /* a surface of isotropic material scatters as a medium does */
        if (lit(c, vx))
            direct2(c, p, vx, rec.p, rt_v3(0, 0, 0), col);
        next.orig = rec.p;
        next.dir = rt_warp_sphere(rt_sampler_get2d(&p->smp));
        att = col;
        vx->pdf = 1.0 / (4.0 * PI);
    } else {
        if (m->kind == RT_MAT_LAMBERTIAN && c->r->lights) {
            if (lit(c, vx))
                direct2(c, p, vx, rec.p, rec.normal, col);
            next.orig = rec.p;
            const double f = rt_nee_scatter(c->r, rec.p, rec.normal, time, rt_sampler_get2d(&p->smp), &next.dir,
                                            &vx->pdf);
            if (f == 0.0)
                return 0;
            att = rt_v3_scale(col, f);
        } else {
            if (!rt_material_scatter(m, &p->ray, &rec, c->r->job.diffuse, &p->smp, &att, &next))
                return 0;
            if (m->kind == RT_MAT_LAMBERTIAN)
                att = col;
        }
    }
    p->thr = rt_v3_mul(p->thr, att);
    p->ray = next;
    return 1;
}

/* Path p to its end; adds its segments to *segments. */
static void trace2(const p2 *c, path *p, double time, uint64_t *segments)
{
    const rt_renderer *r = c->r;
    uint64_t segs = 0;
    vertex v = {0, 0, time, 0.0, &segs};
    for (uint32_t depth = 0; depth < r->job.max_depth; depth++) {
        segs++;
        rt_whit h;
        const int found = rt_nee_closest(r, &p->ray, time, &h);
        v.depth = depth;
        v.base = RT_SAMPLER2_DIM_BOUNCE + c->stride * depth;
        rt_sampler_seek(&p->smp, v.base + RT_SAMPLER2_FLIGHT);
        double tm;
        uint32_t k;
        const int in_medium = c->s->media.media.n && medium_event(c, p, found ? h.t : INFINITY, &tm, &k);
        rt_sampler_seek(&p->smp, v.base + RT_SAMPLER2_SCATTER);
        if (in_medium) {
            scatter_medium(c, p, &v, k, tm);
        } else if (!found) {
            miss2(c, p);
            break;
        } else if (!surface2(c, p, &h, &v)) {
            break;
        }
        if (!path_roulette(r, p, depth))
            break;
    }
    *segments += segs;
}

/* The sample count of c's pixel from its pilot (path.h's rule). */
static uint32_t pilot2(const p2 *c, uint64_t *segments)
{
    const rt_renderer *r = c->r;
    p2 pilot = *c;
    rt_sampler_for_pixel(&pilot.pc.smp, r->job.sampler,
                         rt_rng_pixel_key(r->job.seed ^ RT_ADAPT_PILOT_SALT, (uint64_t)c->pc.y * r->job.width + c->pc.x));
    pilot.pc.aovs = 0;
    double l = 0, l2 = 0;
    for (uint32_t k = 0; k < RT_ADAPT_FIRST; k++) {
        path p;
        double time;
        start2(&pilot, k, &p, &time);
        trace2(&pilot, &p, time, segments);
        const double lum = luminance(p.col);
        l += lum;
        l2 += lum * lum;
    }
    return rt_render_adapt_count(l, l2, RT_ADAPT_FIRST, r->job.noise_threshold, r->job.samples);
}

static p2 context(const rt_renderer *r, uint32_t x, uint32_t y, int aovs)
{
    p2 c = {.r = r,
            .w = r->world,
            .s = r->scene,
            .pn = rt_world_perlin(r->world),
            .pc = pixel_start(r, x, y, pixel_key(r, x, y), aovs),
            .stride = r->lights ? RT_SAMPLER2_LIT_BOUNCE_DIMS : RT_SAMPLER2_BOUNCE_DIMS,
            .cosine = !r->lights && r->job.diffuse == RT_DIFFUSE_LAMBERTIAN};
    return c;
}

uint64_t rt_path2_pixel(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t s0, uint32_t s1, int64_t *px)
{
    pixel_acc acc;
    memset(&acc, 0, sizeof acc);
    uint64_t segs = 0;
    const int extras = r->lay.ch > 3;
    const int adapt = extras && r->lay.count != 0;
    const p2 c = context(r, x, y, extras && (r->lay.albedo || r->lay.normal));
    if (adapt) {
        const uint32_t n = pilot2(&c, &segs);
        s1 = s1 < n ? s1 : n;
        s0 = s0 < s1 ? s0 : s1;
    }
    for (uint32_t s = s0; s < s1; s++) {
        path p;
        double time;
        start2(&c, s, &p, &time);
        trace2(&c, &p, time, &segs);
        add_sample(&acc, &p, c.pc.aovs);
    }
    pixel_store(r, &acc, px, s1 - s0, adapt, c.pc.aovs);
    return segs;
}

rt_vec3 rt_path2_sample(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t sample, uint64_t *segments)
{
    const p2 c = context(r, x, y, 0);
    path p;
    double time;
    start2(&c, sample, &p, &time);
    trace2(&c, &p, time, segments);
    return p.col;
}

uint32_t rt_path2_pilot(const rt_renderer *r, uint32_t x, uint32_t y, uint64_t *segments)
{
    const p2 c = context(r, x, y, 0);
    return pilot2(&c, segments);
}
