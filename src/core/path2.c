/* path2.c - the book-2 path loop: the scenes of "The Next Week" (quads,
 * moving spheres, textures, emitters, constant media, a background colour,
 * the books' camera), for scenes with such content only (rt_scene_is_book2);
 * book 1's scenes keep path.h's loops, their bytes and their speed. It
 * shares path.h's pixel sums, roulette, adaptive rule and buffers, and
 * draws its numbers by sampler.h's book-2 layout. In scenes with emitters
 * it samples them at diffuse vertices (nee.h), unless the job says not. */
#include "path2.h"

#include "caustic.h"
#include "flight.h"
#include "nee.h"
#include "path.h"
#include "path2_start.h"
#include "texture.h"
#include "world.h"

/* The optical depth below which a segment's media are thin enough for
 * inscatter (ln 2: they scatter less than half of its light). Where they
 * scatter more, the free flight's own vertex finds the direct light about
 * as well: at 128 x 128, 64 spp, against 4,096, display-space RMSE and
 * CPU seconds (min of 5-7 interleaved runs) book2-final 9.13 in 0.92 s
 * without inscatter, 7.77 in 1.03 s with (MSE x time 0.81x); cornell-smoke
 * 4.30 in 0.73 s, 4.21 in 0.76 s with this bound, 4.21 in 0.80 s with
 * none (every smoke box's segment). */
#define RT_INSCATTER_THIN 0.69314718055994530942

typedef struct p2 {
    const rt_renderer *r;
    const rt_world *w;
    const rt_scene *s;
    const rt_perlin *pn; /* the world's noise tables */
    pixel_ctx pc;
    uint32_t stride; /* sampler dimensions per bounce (sampler.h) */
    int cosine;      /* lambertian surfaces scatter by material.c's cosine rule (no lights to sample) */
    int inscatter;   /* lights to sample and media: segments' direct in-scattering (inscatter) */
    int caustic;     /* lights to sample and glass spheres, no media: caustic2 */
} p2;

/* The scattering's numbers of the vertex a segment ends at, drawn before
 * the walk that finds it: its 2D number (+RT_SAMPLER2_SCATTER) and, in
 * brute force, its unit-sphere direction. Neither depends on the hit, so
 * the processor works them out while it walks instead of after, in the
 * next walk's chain: cornell-box's brute force 1.2x as fast, same bits. */
typedef struct ahead {
    int drawn, sphered; /* u2 is the 2D number; sphere its direction */
    uint64_t u2;
    rt_vec3 sphere;
} ahead;

typedef struct cvertex { /* a vertex that estimated a caustic (caustic2) */
    uint32_t target;
    rt_vec3 x, n, w; /* point, normal, scattered direction */
} cvertex;

/* The vertex a path is at: the bounce's depth and first dimension, the
 * path's time, the BSDF density of the ray that left the vertex before
 * (0: specular, or the camera's), the segment count, and its scattering's
 * numbers drawn ahead. */
typedef struct vertex {
    uint32_t depth, base;
    double time, pdf;
    uint64_t *segs;
    ahead ahead;
    uint32_t cst; /* caustic chain state (surface2) */
    cvertex cv;
} vertex;

/* A new path for sample `sample`: its camera ray and its time. */
static void start2(const p2 *c, uint32_t sample, path *p, double *time) { rt_path2_start(c->r, &c->pc, sample, p, time); }

/* v's scattering numbers ahead of the walk (the random sampler's depend
 * on the draws before them: none then). */
static inline __attribute__((always_inline)) void look_ahead(const p2 *c, const path *p, vertex *v)
{
    ahead *A = &v->ahead;
    A->drawn = !c->r->no_look_ahead && rt_sampler_peek2d(&p->smp, v->base + RT_SAMPLER2_SCATTER, &A->u2);
    A->sphered = A->drawn && !c->r->lights;
    if (A->sphered)
        A->sphere = rt_warp_sphere(A->u2);
    /* computed here, not sunk past the walk into the branches that use them */
    __asm__ volatile("" : "+m"(*A));
}

/* The scattering's 2D number (the path's sampler is at the bounce's
 * +RT_SAMPLER2_SCATTER): the one drawn ahead when there is one. */
static inline uint64_t scatter_2d(path *p, const vertex *v)
{
    if (!v->ahead.drawn)
        return rt_sampler_get2d(&p->smp);
    rt_sampler_seek(&p->smp, v->base + RT_SAMPLER2_SCATTER + 2);
    return v->ahead.u2;
}

/* Its direction on the unit sphere (rt_warp_sphere's). */
static inline rt_vec3 scatter_sphere(path *p, const vertex *v)
{
    if (!v->ahead.sphered)
        return rt_warp_sphere(rt_sampler_get2d(&p->smp));
    rt_sampler_seek(&p->smp, v->base + RT_SAMPLER2_SCATTER + 2);
    return v->ahead.sphere;
}

static rt_vec3 clamp3(rt_vec3 v) { return rt_v3(clamp01(v.x), clamp01(v.y), clamp01(v.z)); }

/* The background's light for a path that leaves the scene. */
static void miss2(const p2 *c, path *p)
{
    const rt_vec3 bg = rt_path2_background(c->s, p->ray.dir);
    p->col = rt_v3_add(p->col, rt_v3_mul(p->thr, bg));
    if (c->pc.aovs && !p->aov.done)
        p->aov = (aov_rec){1, clamp3(bg), rt_v3(0, 0, 0)};
}

#define PI 3.14159265358979323846

static const rt_nee_bsdf ISOTROPIC = {{0, 0, 0}, {0, 0, 0}, 0.0};
static int lit(const p2 *c, const vertex *v) { return c->r->lights && v->depth + 1 < c->r->job.max_depth; }

/* The light a diffuse vertex at `at` (normal n, zero for isotropic) of
 * albedo gets from a light it samples, when lit (the next segment within the
 * depth limit); by the bounce's light dimensions. Inline: out of line cost
 * a second call a vertex. */
static inline void direct2(const p2 *c, path *p, const vertex *v, rt_vec3 at, rt_nee_bsdf b, rt_vec3 albedo)
{
    rt_sampler_seek(&p->smp, v->base + RT_SAMPLER2_LIGHT);
    p->col = rt_v3_add(p->col, rt_nee_direct(c->r, at, &b, rt_v3_mul(p->thr, albedo), v->time, &p->smp, v->segs));
    rt_sampler_seek(&p->smp, v->base + RT_SAMPLER2_SCATTER);
}

/* The MIS weight of an emitter found through the sphere whose light the
 * vertex before estimated (caustic2); both out of line: the loop keeps its registers. */
static __attribute__((noinline)) double caustic_weight2(const p2 *c, const vertex *v, const rt_whit *h,
                                                        const rt_surface *rec)
{
    return rt_caustic_weight(c->r, v->cv.x, v->cv.n, v->cv.w, v->cv.target, h, rec->p, rec->normal, v->time);
}

/* A lambertian vertex's light through a glass sphere (caustic.h), where the
 * gate says so and the chain's emitter (three segments on) is within depth. */
static __attribute__((noinline)) void caustic2(const p2 *c, path *p, vertex *v, const rt_surface *rec,
                                               rt_vec3 albedo, rt_vec3 dir)
{
    uint32_t target;
    if (!(v->depth + 3 < c->r->job.max_depth) || !rt_caustic_gate(c->r, rec->p, &target))
        return;
    rt_sampler_seek(&p->smp, v->base + RT_SAMPLER2_CAUSTIC);
    const double u = rt_sampler_get1d(&p->smp);
    const uint64_t u2 = rt_sampler_get2d(&p->smp); /* the pair at +12 */
    p->col = rt_v3_add(p->col, rt_caustic_direct(c->r, rec->p, rec->normal, rt_v3_mul(p->thr, albedo), v->time,
                                                 target, u, u2, v->segs));
    v->cst = 1;
    v->cv = (cvertex){target, rec->p, rec->normal, dir};
}

/* Scattering in medium k at distance t: the phase function's direction
 * (isotropic), the medium's colour. */
static void scatter_medium(const p2 *c, path *p, vertex *v, uint32_t k, double t, int forced)
{
    const rt_material *m = &c->s->materials[c->s->media.media.items[k].material];
    const rt_vec3 at = rt_ray_at(&p->ray, t);
    const rt_vec3 albedo = rt_texture_albedo(c->s, c->pn, m, 0, 0, at);
    if (c->pc.aovs && !p->aov.done)
        p->aov = (aov_rec){1, clamp3(albedo), rt_v3(0, 0, 0)};
    if (lit(c, v) && !forced)
        direct2(c, p, v, at, ISOTROPIC, albedo);
    p->thr = rt_v3_mul(p->thr, albedo);
    p->ray.orig = at;
    p->ray.dir = scatter_sphere(p, v);
    v->pdf = forced ? -1.0 : 1.0 / (4.0 * PI); /* forced: an emitter found next counts nothing (rt_nee_weight) */
}

/* The light the media scatter into the path's segment straight from the
 * emitters (its direct in-scattering), when the segment leaves the camera
 * or a specular vertex and its media are thin (optical depth below
 * RT_INSCATTER_THIN): the glow a viewer sees in thin fog, which the free
 * flight finds only on the few segments it scatters on, at a point chosen
 * without regard to the light. Here a point y on a light first
 * (rt_lights_point), then with probability q = 1 - T (T the segment's
 * transmittance through its media spans S: as many shadow rays as the
 * flight's own scattering would trace) a distance along the segment,
 * equi-angular about y (Kulla and Fajardo: density h / ((b - a)(h^2 +
 * (s - s_y)^2)), h the distance of y from the line, b - a the angle the
 * spans' extent subtends from y), which cancels the light's inverse
 * square; there the isotropic phase function toward y, weighted by the
 * media's density and albedo and the transmittance up to the point
 * (rt_nee_toward: the shadow ray, under the shadow-ray roulette). The
 * segment's own free flight still scatters, for the indirect light alone:
 * its vertex samples no light, and an emitter its next segment finds
 * counts nothing (rt_nee_weight of the density -1). Returns 1 when it
 * applies to the segment (then the flight's vertex is so). Its numbers:
 * the bounce's +10 (the distance), +11 (the light; its rest decides q,
 * then the roulette), +12-13 (the point on it) (sampler.h). Unbiased:
 * test_lights's furnace with fog. */
static int inscatter(const p2 *c, path *p, const vertex *v, const rt_spans *S)
{
    const rt_span *sp = S->sp;
    const uint32_t ns = S->n;
    if (!(c->inscatter && v->pdf == 0.0 && lit(c, v) && ns && S->whole < RT_INSCATTER_THIN))
        return 0;
    const double len = S->len, whole = S->whole;
    double ta = INFINITY, tb = 0; /* the spans' extent */
    for (uint32_t i = 0; i < ns; i++) {
        ta = sp[i].a < ta ? sp[i].a : ta;
        tb = sp[i].b > tb ? sp[i].b : tb;
    }
    rt_sampler_seek(&p->smp, v->base + RT_SAMPLER2_INSCATTER);
    const double ud = rt_sampler_get1d(&p->smp), ul = rt_sampler_get1d(&p->smp);
    rt_light_point lp;
    if (!rt_lights_point(c->r->lights, v->time, ul, rt_sampler_get2d(&p->smp), &lp))
        return 1;
    const double q = rt_det_one_minus_exp_neg(whole);
    if (!(lp.rest < q))
        return 1;
    /* equi-angular about y: s along the unit direction w, y's foot at s_y */
    const rt_vec3 w = rt_v3_scale(p->ray.dir, 1.0 / len), dy = rt_v3_sub(lp.p, p->ray.orig);
    const double s_y = rt_v3_dot(dy, w), h = rt_v3_len(rt_v3_sub(dy, rt_v3_scale(w, s_y)));
    if (!(h > 1e-9))
        return 1; /* y on the line: the segment's light meets it head-on, a set of measure zero */
    const double th_a = rt_det_atan((ta * len - s_y) / h), th_b = rt_det_atan((tb * len - s_y) / h);
    if (!(th_b > th_a))
        return 1;
    const double sd = s_y + h * rt_det_tan(th_a + ud * (th_b - th_a));
    const double pdf_s = h / ((th_b - th_a) * (h * h + (sd - s_y) * (sd - s_y)));
    const double t = sd / len;
    double dens = 0, depth = 0; /* at t, and up to it */
    for (uint32_t i = 0; i < ns; i++) {
        if (sp[i].a <= t && sp[i].b > t)
            dens += sp[i].density;
        const double e = t < sp[i].b ? t : sp[i].b;
        if (e > sp[i].a)
            depth += sp[i].density * (e - sp[i].a) * len;
    }
    if (!(dens > 0))
        return 1; /* between spans */
    const rt_vec3 at = rt_ray_at(&p->ray, t);
    rt_vec3 albedo = rt_v3(0, 0, 0); /* the live media's, each by its density */
    for (uint32_t i = 0; i < ns; i++)
        if (sp[i].a <= t && sp[i].b > t) {
            const rt_material *m = &c->s->materials[c->s->media.media.items[sp[i].medium].material];
            albedo = rt_v3_add(albedo, rt_v3_scale(rt_texture_albedo(c->s, c->pn, m, 0, 0, at), sp[i].density));
        }
    const double k = rt_det_exp_neg(depth) / (4.0 * PI * pdf_s * lp.pdf * q);
    const rt_vec3 weight = rt_v3_scale(rt_v3_mul(p->thr, albedo), k);
    p->col = rt_v3_add(p->col, rt_nee_toward(c->r, at, &lp, weight, lp.rest / q, v->time, v->segs));
    return 1;
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
            /* cst 3: a caustic chain the vertex before estimated (caustic.h) */
            const double w = vx->cst == 3 ? caustic_weight2(c, vx, h, &rec)
                             : c->r->lights ? rt_nee_weight(c->r, &p->ray, vx->pdf, h, time)
                                            : 1.0;
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
        p->ray = (rt_ray){rec.p, rt_warp_lambert_of(scatter_sphere(p, vx), rec.normal)};
        return 1;
    }
    const uint32_t st = vx->cst; /* the caustic chain's state (caustic2): none in brute force, so read after it */
    vx->cst = 0;
    rt_vec3 att;
    rt_ray next;
    if (m->kind == RT_MAT_ISOTROPIC) { /* a surface of isotropic material scatters as a medium does */
        if (lit(c, vx))
            direct2(c, p, vx, rec.p, ISOTROPIC, col);
        next.orig = rec.p;
        next.dir = scatter_sphere(p, vx);
        att = col;
        vx->pdf = 1.0 / (4.0 * PI);
    } else {
        if (m->kind == RT_MAT_LAMBERTIAN && c->r->lights) {
            if (lit(c, vx))
                direct2(c, p, vx, rec.p, (rt_nee_bsdf){.n = rec.normal}, col);
            next.orig = rec.p;
            const double f = rt_nee_scatter(c->r, rec.p, rec.normal, time, scatter_2d(p, vx), &next.dir, &vx->pdf);
            if (c->caustic)
                caustic2(c, p, vx, &rec, col, next.dir);
            if (f == 0.0)
                return 0;
            att = rt_v3_scale(col, f);
        } else {
            /* a fuzzy metal samples the lights too: its scattered direction
             * has a density (rt_warp_fuzz_pdf), so MIS weighs the two */
            const int fuzzy = m->kind == RT_MAT_METAL && m->fuzz > 0.0 && c->r->lights;
            const rt_vec3 mirror = fuzzy ? rt_v3_reflect(rt_v3_unit(p->ray.dir), rec.normal) : rec.normal;
            if (fuzzy && lit(c, vx))
                direct2(c, p, vx, rec.p, (rt_nee_bsdf){rec.normal, mirror, m->fuzz}, m->albedo);
            if (!rt_material_scatter(m, &p->ray, &rec, c->r->job.diffuse, &p->smp, &att, &next))
                return 0;
            if ((st == 1 || st == 2) && m->kind == RT_MAT_DIELECTRIC && h->kind == RT_SHAPE_SPHERE &&
                h->index == rt_lights_target_sphere(c->r->lights, vx->cv.target) &&
                rt_v3_dot(next.dir, rec.normal) < 0.0) /* refracted through the target sphere */
                vx->cst = st + 1;
            if (m->kind == RT_MAT_LAMBERTIAN)
                att = col;
            if (fuzzy)
                vx->pdf = rt_warp_fuzz_pdf(mirror, m->fuzz, rt_v3_unit(next.dir));
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
    vertex v = {0, 0, time, 0.0, &segs, {0, 0, 0, {0, 0, 0}}, 0, {0, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    rt_whit last; /* the last segment's hit (its surface, or a medium's flight short of it) */
    int have_last = 0;
    for (uint32_t depth = 0; depth < r->job.max_depth; depth++) {
        segs++;
        v.depth = depth;
        v.base = RT_SAMPLER2_DIM_BOUNCE + c->stride * depth;
        look_ahead(c, p, &v);
        rt_whit h;
        const int found = depth == 0 && c->pc.pn >= 0
                              ? rt_world_closest_listed(c->w, r->wlists, c->pc.pfirst, c->pc.pn, &p->ray, time, T_MIN,
                                                        INFINITY, &h)
                              : rt_nee_closest(r, &p->ray, time, have_last ? &last : NULL, &h);
        rt_sampler_seek(&p->smp, v.base + RT_SAMPLER2_FLIGHT);
        double tm;
        uint32_t k;
        rt_spans S;
        S.n = 0;
        if (c->s->media.media.n)
            rt_flight_spans_of(c->s, c->w, &p->ray, found ? h.t : INFINITY, &S);
        const int in_medium = rt_flight_event(&p->smp, &S, &tm, &k);
        const int forced = c->inscatter && inscatter(c, p, &v, &S);
        rt_sampler_seek(&p->smp, v.base + RT_SAMPLER2_SCATTER);
        if (in_medium) {
            v.cst = 0;
            scatter_medium(c, p, &v, k, tm, forced);
        } else if (!found) {
            miss2(c, p);
            break;
        } else if (!surface2(c, p, &h, &v)) {
            break;
        }
        if (!path_roulette(r, p, depth))
            break;
        last = h, have_last = found;
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
            .stride = !r->lights              ? RT_SAMPLER2_BOUNCE_DIMS
                      : r->scene->media.media.n ? RT_SAMPLER2_LIT_MEDIA_BOUNCE_DIMS
                      : r->light_targets        ? RT_SAMPLER2_LIT_CAUSTIC_BOUNCE_DIMS
                                                : RT_SAMPLER2_LIT_BOUNCE_DIMS,
            .caustic = r->lights && r->light_targets && !r->scene->media.media.n && !r->no_caustic,
            .cosine = !r->lights && r->job.diffuse == RT_DIFFUSE_LAMBERTIAN,
            .inscatter = r->lights && r->scene->media.media.n};
    if (r->wlists) /* the camera rays' list of the pixel's tile (world_lists.c) */
        c.pc.pn = rt_world_lists_tile(r->wlists, x, y, &c.pc.pfirst);
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
