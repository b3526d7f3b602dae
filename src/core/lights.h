/* lights.h - the scene's emitters as light sources for next-event
 * estimation (path2.c): every static sphere, quad and moving sphere whose
 * material is an emitter (instances are already flattened to such shapes),
 * one chosen per path vertex uniformly (or in proportion to its power),
 * and a direction toward it with its solid-angle density: quads by a
 * uniform point of their area, spheres by the cone of directions they
 * subtend. The caller traces the direction and takes the light's emission
 * where the ray hits it (world.h's surface record: front-face-only and
 * two-sided emitters, textures, all as a path that hits it by chance), so
 * the density is all this module answers for. Built with the accelerator
 * (rt_accel_lights), for scenes with book-2 content and emitters. */
#ifndef RT_LIGHTS_H
#define RT_LIGHTS_H

#include <stddef.h>
#include <stdint.h>

#include "scene.h"
#include "vec.h"

typedef struct rt_lights rt_lights;

/* How a vertex chooses its light. */
typedef enum rt_lights_rule {
    RT_LIGHTS_POWER = 0,   /* in proportion to emitted power (luminance x area x pi, twice for two-sided) */
    RT_LIGHTS_UNIFORM = 1, /* each light alike */
} rt_lights_rule;

/* The rule a render uses (a benchmark build may define another). Uniform:
 * on simple-light (a sphere light of 12 times the quad light's power, the
 * quad nearer what the camera sees; 80 x 45, Sobol, one thread, against
 * 8192 spp), display-space RMSE 6.89 / 3.01 / 1.46 at 16 / 64 / 256 spp
 * against power's 8.24 / 3.87 / 1.70, in the same time (0.28 s against
 * 0.30 s at 64 spp). The other named scenes have one light. */
#ifndef RT_LIGHTS_RULE
#define RT_LIGHTS_RULE RT_LIGHTS_UNIFORM
#endif

/* *out is NULL (and RT_OK) when s has no emitter shape. */
int rt_lights_build(rt_lights **out, const rt_scene *s, rt_lights_rule rule);
void rt_lights_free(rt_lights *l);
uint32_t rt_lights_count(const rt_lights *l);
size_t rt_lights_bytes(const rt_lights *l);

/* A direction toward a light, as rt_lights_sample gives it. */
typedef struct rt_light_dir {
    rt_vec3 dir;          /* unit */
    uint32_t kind, index; /* the light's shape (world.h's rt_shape_kind, its index) */
    uint32_t material;    /* the shape's */
    uint32_t light;       /* its place in the list (rt_lights_pdf_of) */
    double pdf;           /* the density of dir (rt_lights_pdf's), for the chosen point on a quad */
    double emit;          /* the light's luminance (a textured one counts as white) */
    double rest;          /* u's fraction within the chosen light's share: a number in [0, 1)
                             independent of the choice, for the caller's own use */
} rt_light_dir;

/* A light to sample from point p at time `time`: chosen by u in [0, 1),
 * a direction toward it by the 2D number u2 (warp.h's two fractions).
 * Returns 1 with *out, 0 when the chosen light offers no direction from p
 * (p inside its sphere, in its quad's plane, or behind a quad that emits
 * from its front face only: its light could not reach p). */
int rt_lights_sample(const rt_lights *l, rt_vec3 p, double time, double u, uint64_t u2, rt_light_dir *out);

/* A point on a light, as rt_lights_point gives it. */
typedef struct rt_light_point {
    rt_vec3 p, n;         /* the point and the light's unit normal there (a sphere's outward) */
    uint32_t kind, index; /* the light's shape */
    uint32_t material;
    int one_sided;        /* a quad that emits toward n only */
    double pdf;           /* per unit area, the light's choice included */
    double emit;          /* the light's luminance */
    double rest;          /* as rt_light_dir's */
} rt_light_point;

/* A point on a light at time `time`, seen from nowhere in particular (a
 * medium's in-scattering along a whole segment, path2.c): the light chosen
 * by u as rt_lights_sample does, the point uniform over its area (a
 * quad's, a sphere's whole surface) by u2. Returns 0 for a light of no
 * area. */
int rt_lights_point(const rt_lights *l, double time, double u, uint64_t u2, rt_light_point *out);

/* The density (per unit solid angle, the light's choice included) with
 * which rt_lights_sample gives unit direction dir from p, for a ray
 * p + t dir that first meets shape (kind, index) at distance t; 0 when
 * that shape is no light or is not sampled from p. */
double rt_lights_pdf(const rt_lights *l, rt_vec3 p, double time, rt_vec3 dir, uint32_t kind, uint32_t index,
                     double t);
/* The same for the light at place `slot` of the list (rt_light_dir.light),
 * without looking its shape up. */
double rt_lights_pdf_of(const rt_lights *l, uint32_t slot, rt_vec3 p, double time, rt_vec3 dir, double t);

/* The list as rows of quads, for path_lanes.c's vector code (the same
 * numbers rt_lights_sample and rt_lights_pdf_of use): each light's corner
 * a and edges b, c, unit normal n, area, probability, luminance, the
 * cumulative probability before the next (cdf), one_sided (1.0 or 0.0)
 * and its quad. */
#define RT_LIGHTS_QUAD_ROWS 8
typedef struct rt_light_quads {
    double a[3][RT_LIGHTS_QUAD_ROWS], b[3][RT_LIGHTS_QUAD_ROWS], c[3][RT_LIGHTS_QUAD_ROWS], n[3][RT_LIGHTS_QUAD_ROWS];
    double area[RT_LIGHTS_QUAD_ROWS], prob[RT_LIGHTS_QUAD_ROWS], emit[RT_LIGHTS_QUAD_ROWS];
    double cdf[RT_LIGHTS_QUAD_ROWS], one_sided[RT_LIGHTS_QUAD_ROWS];
    int64_t quad[RT_LIGHTS_QUAD_ROWS];
} rt_light_quads;

/* Fills *q and returns the count of lights when they are all quads and at
 * most RT_LIGHTS_QUAD_ROWS; else 0. */
uint32_t rt_lights_quads(const rt_lights *l, rt_light_quads *q);

/* Sampling targets: the scene's static glass spheres, which emit nothing
 * but through which a diffuse vertex's light can come (a caustic: the
 * glass between the light and the vertex, or beyond it), and which only a
 * path that passes through them finds. A lambertian vertex of the path
 * loop aims a share of its scattered directions at them (nee.h). */
uint32_t rt_lights_target_count(const rt_lights *l);

/* A direction *dir (unit) from p toward one of the targets, uniform in the
 * cone it subtends: the target chosen by the fraction a (its remainder
 * places the direction's angle from the axis), the azimuth by the
 * fraction b. Returns 0 when p is inside the chosen sphere. Needs
 * rt_lights_target_count(l) > 0. */
int rt_lights_target_sample(const rt_lights *l, rt_vec3 p, double time, uint32_t a, uint32_t b, rt_vec3 *dir);

/* The density (per unit solid angle, the target's choice included) with
 * which rt_lights_target_sample gives the direction of dir (any length)
 * from p: a sum over the targets whose sphere the line meets. */
double rt_lights_target_pdf(const rt_lights *l, rt_vec3 p, double time, rt_vec3 dir);

/* Target k's shape: the static sphere of that index (RT_SHAPE_SPHERE). */
uint32_t rt_lights_target_sphere(const rt_lights *l, uint32_t k);

/* The density per unit area, the light's choice included, with which
 * rt_lights_point gives a point of light (kind, index); 0 if it is none. */
double rt_lights_area_pdf(const rt_lights *l, uint32_t kind, uint32_t index);

/* Whether x lies in a target sphere's shadow, where the light it focuses
 * falls: its centre within reach times its radius of the segment from x
 * to a light's centre. 1 with *target, the first such; else 0. */
int rt_lights_target_between(const rt_lights *l, rt_vec3 x, double reach, uint32_t *target);

#endif
