/* nee.h - next-event estimation for the book-2 path loop (path2.c): at a
 * vertex that scatters with a density (lambertian, isotropic, fuzzy
 * metal), the light of one emitter reached by a shadow ray toward it
 * (lights.h); the light thin media scatter along a segment
 * (rt_nee_toward, for path2.c's inscatter); and the weight of the
 * light a BSDF-sampled ray finds on an emitter; the two strategies are
 * combined by multiple importance sampling with the power heuristic (the
 * weights of a direction sum to 1, so the sum is unbiased). A shadow ray
 * that crosses constant media carries their transmittance
 * exp(-sum density x length), computed, not sampled: no numbers drawn,
 * the same bits on every machine (detmath.h). Core-internal. */
#ifndef RT_NEE_H
#define RT_NEE_H

#include <math.h>
#include <stdint.h>

#include "accel.h"
#include "lights.h"
#include "render.h"
#include "sampler.h"
#include "world.h"

/* The closest surface of ray at time `time` with t > 0.001 (path.h's
 * T_MIN): one walk of the world's tree, which holds the static spheres
 * too (a tie goes to the quads and moving spheres: a fixed rule), or
 * inside a glass sphere none (from: the path's last hit, or NULL; the same
 * answer). Inline: the path loop's every segment. */
static inline int rt_nee_closest(const rt_renderer *r, const rt_ray *ray, double time, const rt_whit *from,
                                 rt_whit *h)
{
    return rt_world_closest_from(r->world, ray, time, 0.001, INFINITY, from, h);
}

/* Shadow-ray roulette (with the job's roulette; nee.c's, and path_lanes.c's
 * in its lanes): a shadow ray whose light, were it unoccluded, would add less than a threshold (luminance of
 * throughput x albedo x emission x the BSDF over the light's density) is
 * traced with probability (that luminance / the threshold), its light
 * divided by that probability: unbiased, and faint vertices spend fewer
 * shadow rays. The thresholds, by CPU seconds x display-space MSE
 * (sampling version 10, docs/SAMPLING.md): in media (isotropic vertices
 * and path2.c's in-scattering: book2-final's thin fog, whose shadow rays
 * are most of its shadow rays and mostly occluded) 0.05; at surfaces 0.005,
 * since a surface's faint shadow rays are cheap and light the dark
 * regions where the viewer sees the noise (book3-final's ceiling, lit only
 * through the room: 0.05 there cost 1.25x the MSE at 8 spp, 256 x 256, for
 * 7 % less time). */
#define RT_NEE_SHADOW_KEEP_MEDIA 0.05
#define RT_NEE_SHADOW_KEEP_SURFACE 0.005

/* A vertex's scattering, as next-event estimation weighs a direction by
 * it: lambertian about normal n; isotropic (n zero); or a fuzzy metal
 * (fuzz > 0: the mirror direction m, unit, and the surface normal n). */
typedef struct rt_nee_bsdf {
    rt_vec3 n, m;
    double fuzz;
} rt_nee_bsdf;

/* Light at vertex p reaching the pixel through the vertex's scattering:
 * weight (the path's throughput times the vertex's albedo) times the BSDF
 * density pdf_bsdf of the shadow ray's direction (lambertian: cos / pi,
 * which is f cos; isotropic: 1 / 4pi, which is f; fuzzy metal: the
 * density of its scattered direction, rt_warp_fuzz_pdf, zero below the
 * surface, which is f cos as the path's throughput takes the albedo alone),
 * times the emission, over the light's density, weighted. Draws a 1D and
 * a 2D number from smp (the light and the point; the 1D number's rest
 * also decides the shadow-ray roulette, nee.c). Adds the shadow ray, when
 * traced, to *segments. */
rt_vec3 rt_nee_direct(const rt_renderer *r, rt_vec3 p, const rt_nee_bsdf *b, rt_vec3 weight, double time,
                      rt_sampler *smp, uint64_t *segments);

/* A lambertian vertex's scattered direction *dir from p (normal n) by the
 * 2D number u: cosine-weighted, or, in a scene with sampling targets
 * (lights.h), a mixture of that and directions aimed at them. *pdf: its
 * density (for the MIS weight of an emitter the ray finds). Returns the
 * factor of the path's throughput besides the albedo (cos / pi over the
 * density; 1 for the cosine alone), 0 when the path ends (a direction
 * below the surface: nothing is reflected there). */
double rt_nee_scatter(const rt_renderer *r, rt_vec3 p, rt_vec3 n, double time, uint64_t u, rt_vec3 *dir,
                      double *pdf);

/* The density with which rt_nee_scatter gives direction dir (any length)
 * from p (normal n): 0 below the surface. */
double rt_nee_scatter_pdf(const rt_renderer *r, rt_vec3 p, rt_vec3 n, double time, rt_vec3 dir);

/* The weight of the emission a BSDF-sampled ray (from its origin, where
 * the vertex's BSDF density of its direction was pdf_bsdf) finds at hit h:
 * 1 after a specular vertex (pdf_bsdf 0); 0 when pdf_bsdf is negative, a
 * vertex whose direct light was estimated without MIS. */
double rt_nee_weight(const rt_renderer *r, const rt_ray *ray, double pdf_bsdf, const rt_whit *h, double time);

/* The light that point lp of a light sends to x, per unit of the light's
 * area, times weight: its emission toward x times the transmittance of the
 * media between, times the cosine at the light over the squared distance;
 * zero when anything (the light's own near side too) stands between.
 * Under the job's roulette a faint one is traced with a probability
 * (rt_nee_direct's rule, at the media's threshold), decided by u in
 * [0, 1). Adds the shadow ray, when traced, to *segments. */
rt_vec3 rt_nee_toward(const rt_renderer *r, rt_vec3 x, const rt_light_point *lp, rt_vec3 weight, double u,
                      double time, uint64_t *segments);

/* The emission of emitter hit h (its material set) seen along ray: its texture's value on its
 * emitting face(s), else zero. */
rt_vec3 rt_nee_emitted(const rt_renderer *r, const rt_whit *h, const rt_ray *ray, double time);

#endif
