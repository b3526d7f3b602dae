/* nee.c - next-event estimation and its MIS weights (nee.h). */
#include "nee.h"

#include <math.h>

#include "detmath.h"
#include "lights.h"
#include "texture.h"
#include "warp.h"

#define T_MIN 0.001 /* path.h's shadow-acne bias, as rt_nee_closest's */
#define PI 3.14159265358979323846

/* rt_nee_emitted's general case: the face and the texture at the hit. */
static rt_vec3 surface_emission(const rt_renderer *r, const rt_material *m, const rt_whit *h, const rt_ray *ray,
                                double time)
{
    rt_surface rec;
    double u, v;
    rt_world_surface(r->world, h, ray, time, m->texture != 0, &rec, &u, &v);
    if (!rec.front_face && !(m->flags & RT_MAT_TWO_SIDED))
        return rt_v3(0, 0, 0);
    return rt_texture_albedo(r->scene, rt_world_perlin(r->world), m, u, v, rec.p);
}

/* rt_nee_emitted, inline in shadow_light: an untextured two-sided emitter
 * (book 2's lights) sends its emission from every point of both faces, so
 * no surface record (113 instructions a shadow ray that reached such a
 * light, of some 900: docs/PERFORMANCE.md). */
static inline rt_vec3 emission(const rt_renderer *r, const rt_whit *h, const rt_ray *ray, double time)
{
    const rt_material *m = &r->scene->materials[h->material];
    if (m->kind != RT_MAT_EMITTER)
        return rt_v3(0, 0, 0);
    if (!m->texture && (m->flags & RT_MAT_TWO_SIDED))
        return m->emit; /* rt_texture_albedo's value */
    return surface_emission(r, m, h, ray, time);
}

rt_vec3 rt_nee_emitted(const rt_renderer *r, const rt_whit *h, const rt_ray *ray, double time)
{
    return emission(r, h, ray, time);
}

/* The transmittance of the media along ray (unit direction) over
 * (T_MIN, t). */
static double transmittance(const rt_renderer *r, const rt_ray *ray, double t)
{
    const rt_scene *s = r->scene;
    double depth = 0;
    for (uint32_t k = 0; k < s->media.media.n; k++) {
        double a, b;
        if (!rt_world_medium_span(r->world, k, ray, &a, &b))
            continue;
        a = a > T_MIN ? a : T_MIN;
        b = b < t ? b : t;
        if (b > a)
            depth += s->media.media.items[k].density * (b - a);
    }
    return depth > 0.0 ? rt_det_exp_neg(depth) : 1.0;
}

/* A lambertian vertex in a scene with sampling targets (lights.h: its
 * glass spheres) aims one in RT_NEE_AIM_SLOTS of its scattered directions
 * at them (0: none). Why: book3-final's caustic, the light the glass
 * sphere focuses on the floor in its own shadow, reaches the floor only
 * through the sphere, and every vertex that sees that bright spot finds it
 * by chance; those rare paths were most of the squared error (the worst 1 %
 * of the pixels held 48 % of it at 64 spp, 128 x 128). Measured there
 * (docs/SAMPLING.md): 1 in 2, 4, 8, 16. */
#ifndef RT_NEE_AIM_SLOTS
#define RT_NEE_AIM_SLOTS 8u
#endif

/* The density of a lambertian vertex's scattered direction dir (any length)
 * from p, whose cosine density is pdf_cos: the mixture rt_nee_scatter
 * draws from. */
static double scatter_pdf(const rt_renderer *r, rt_vec3 p, rt_vec3 dir, double time, double pdf_cos)
{
    const double share = 1.0 / RT_NEE_AIM_SLOTS;
    return (1.0 - share) * pdf_cos + share * rt_lights_target_pdf(r->lights, p, time, dir);
}

double rt_nee_scatter(const rt_renderer *r, rt_vec3 p, rt_vec3 n, double time, uint64_t u, rt_vec3 *dir,
                      double *pdf)
{
    const uint32_t slots = RT_NEE_AIM_SLOTS;
    if (!slots || !r->light_targets) { /* cosine-weighted */
        const rt_vec3 d = rt_warp_lambert(u, n);
        *dir = d;
        *pdf = rt_v3_dot(d, n) / (rt_v3_len(d) * PI);
        return 1.0;
    }
    /* slot (slots - 1) of the first fraction aims at a target, the others
     * take the cosine; the fraction's remainder in its slot goes on */
    const uint64_t x = (uint64_t)(uint32_t)(u >> 32) * slots;
    const uint32_t slot = (uint32_t)(x >> 32), rest = (uint32_t)x;
    rt_vec3 d;
    double c;
    if (slot + 1 < slots) {
        const uint64_t a = (((uint64_t)slot << 32) | rest) / (slots - 1);
        d = rt_warp_lambert(a << 32 | (uint32_t)u, n);
        c = rt_v3_dot(d, n) / rt_v3_len(d);
    } else if (!rt_lights_target_sample(r->lights, p, time, rest, (uint32_t)u, &d) || !((c = rt_v3_dot(d, n)) > 0.0))
        return 0.0;
    *dir = d;
    *pdf = scatter_pdf(r, p, d, time, c / PI);
    return c / (PI * *pdf);
}

double rt_nee_scatter_pdf(const rt_renderer *r, rt_vec3 p, rt_vec3 n, double time, rt_vec3 dir)
{
    const double c = rt_v3_dot(dir, n) / rt_v3_len(dir);
    if (!(c > 0.0))
        return 0.0;
    return RT_NEE_AIM_SLOTS && r->light_targets ? scatter_pdf(r, p, dir, time, c / PI) : c / PI;
}

static double luma(rt_vec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

/* The shadow-ray roulette's decision for a shadow ray whose light, were
 * it unoccluded, has luminance est, by u in [0, 1), under threshold lim:
 * the chance it is traced with (1 without the job's roulette or from lim
 * up), or 0 when it is not. */
static double shadow_keep(const rt_renderer *r, double est, double u, double lim)
{
    if (!r->job.roulette || !(est < lim))
        return 1.0;
    const double keep = est / lim;
    return u < keep ? keep : 0.0;
}

/* The shadow ray (counted in *segments) along ray (unit direction) to the
 * light (kind, index) of material `material`: 1 when the light is the
 * first thing it meets, at a distance of at least min_t (*h its hit), with
 * *light its emission there times the media's transmittance up to it; 0
 * when something (or no emission) is there. */
static int shadow_light(const rt_renderer *r, const rt_ray *ray, uint32_t kind, uint32_t index, uint32_t material,
                        double min_t, double time, rt_whit *h, rt_vec3 *light, uint64_t *segments)
{
    ++*segments;
    *h = (rt_whit){0.0, kind, index, material};
    if (!rt_world_shape_t(r->world, kind, index, ray, time, T_MIN, &h->t) || h->t < min_t ||
        rt_world_occluded(r->world, ray, time, T_MIN, h->t, kind, index))
        return 0;
    const rt_vec3 le = emission(r, h, ray, time);
    if (le.x == 0.0 && le.y == 0.0 && le.z == 0.0)
        return 0;
    *light = r->scene->media.media.n ? rt_v3_scale(le, transmittance(r, ray, h->t)) : le;
    return 1;
}

rt_vec3 rt_nee_direct(const rt_renderer *r, rt_vec3 p, const rt_nee_bsdf *b, rt_vec3 weight, double time,
                      rt_sampler *smp, uint64_t *segments)
{
    const rt_vec3 n = b->n;
    const rt_vec3 none = {0, 0, 0};
    const double u = rt_sampler_get1d(smp);
    const uint64_t u2 = rt_sampler_get2d(smp);
    rt_light_dir ld;
    if (!rt_lights_sample(r->lights, p, time, u, u2, &ld))
        return none;
    rt_ray ray = {p, ld.dir};
    const int iso = n.x == 0.0 && n.y == 0.0 && n.z == 0.0;
    const double cosine = iso ? 1.0 : rt_v3_dot(ray.dir, n);
    if (!(cosine > 0.0)) /* below a lambertian surface: it reflects nothing there */
        return none;
    const double pdf_bsdf = iso                ? 1.0 / (4.0 * PI)
                            : b->fuzz > 0.0 ? rt_warp_fuzz_pdf(b->m, b->fuzz, ray.dir)
                                            : cosine / PI;
    if (!(pdf_bsdf > 0.0)) /* outside a fuzzy metal's ball of directions */
        return none;
    const int aim = !iso && !(b->fuzz > 0.0) && RT_NEE_AIM_SLOTS > 0 && r->light_targets;
    const double keep = shadow_keep(r, luma(weight) * ld.emit * pdf_bsdf / ld.pdf, ld.rest,
                                    iso ? RT_NEE_SHADOW_KEEP_MEDIA : RT_NEE_SHADOW_KEEP_SURFACE);
    rt_whit h; /* rt_nee_closest's hit if nothing stands in front of the light */
    rt_vec3 light;
    if (keep == 0.0 || !shadow_light(r, &ray, ld.kind, ld.index, ld.material, 0.0, time, &h, &light, segments))
        return none;
    const double pdf_light = rt_lights_pdf_of(r->lights, ld.light, p, time, ray.dir, h.t);
    if (!(pdf_light > 0.0))
        return none;
    const double pdf_scatter = aim ? scatter_pdf(r, p, ray.dir, time, pdf_bsdf) : pdf_bsdf;
    const double w = r->job.light == RT_LIGHT_NEE_ONLY
                         ? 1.0
                         : pdf_light * pdf_light / (pdf_light * pdf_light + pdf_scatter * pdf_scatter);
    return rt_v3_scale(rt_v3_mul(weight, light), pdf_bsdf * w / (pdf_light * keep));
}

double rt_nee_weight(const rt_renderer *r, const rt_ray *ray, double pdf_bsdf, const rt_whit *h, double time)
{
    if (pdf_bsdf < 0.0) /* the vertex's direct light was estimated otherwise (path2.c's in-scattering) */
        return 0.0;
    if (!(pdf_bsdf > 0.0))
        return 1.0;
    const double len = rt_v3_len(ray->dir);
    const double pl = rt_lights_pdf(r->lights, ray->orig, time, rt_v3_scale(ray->dir, 1.0 / len), h->kind,
                                    h->index, h->t * len);
    if (r->job.light == RT_LIGHT_NEE_ONLY) /* what NEE cannot reach keeps its BSDF-sampled light */
        return pl > 0.0 ? 0.0 : 1.0;
    return pdf_bsdf * pdf_bsdf / (pdf_bsdf * pdf_bsdf + pl * pl);
}

rt_vec3 rt_nee_toward(const rt_renderer *r, rt_vec3 x, const rt_light_point *lp, rt_vec3 weight, double u,
                      double time, uint64_t *segments)
{
    const rt_vec3 none = {0, 0, 0};
    const rt_vec3 d = rt_v3_sub(lp->p, x);
    const double d2 = rt_v3_len2(d), dist = sqrt(d2), facing = rt_v3_dot(d, lp->n);
    if (!(dist > 0.0) || facing == 0.0 || (lp->one_sided && facing > 0.0))
        return none; /* x in the light's plane, or behind a face that emits nothing toward it */
    const double g = fabs(facing) / (dist * d2); /* the cosine at the light over the squared distance */
    const double keep = shadow_keep(r, luma(weight) * lp->emit * g, u, RT_NEE_SHADOW_KEEP_MEDIA);
    const rt_ray ray = {x, rt_v3_scale(d, 1.0 / dist)};
    rt_whit h;
    rt_vec3 light; /* none when the light's own near side, or another shape, stands in front of the point */
    if (keep == 0.0 ||
        !shadow_light(r, &ray, lp->kind, lp->index, lp->material, dist * (1.0 - 1e-7), time, &h, &light, segments))
        return none;
    return rt_v3_scale(rt_v3_mul(weight, light), g / keep);
}
