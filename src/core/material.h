/* material.h - how the three book materials scatter a ray, and the surface
 * record an intersection produces. */
#ifndef RT_MATERIAL_H
#define RT_MATERIAL_H

#include "sampler.h"
#include "scene.h"
#include "vec.h"

/* Diffuse models of the book's diffuse chapter (seed 002). */
typedef enum rt_diffuse {
    RT_DIFFUSE_LAMBERTIAN = 0, /* normal + random unit vector (cos law) */
    RT_DIFFUSE_SPHERE = 1,     /* normal + random point in unit sphere */
    RT_DIFFUSE_HEMISPHERE = 2, /* uniform over the hemisphere */
} rt_diffuse;

/* "lambertian", "sphere", "hemisphere"; and back (-1 when unknown). */
const char *rt_diffuse_name(rt_diffuse model);
int rt_diffuse_parse(const char *name);

typedef struct rt_surface {
    rt_vec3 p;      /* hit point */
    rt_vec3 normal; /* unit, facing against the incoming ray */
    double t;
    int front_face; /* 1 when the ray hit the outside */
} rt_surface;

/* Builds the surface record of sphere sp hit by ray at t. */
void rt_surface_from_sphere(rt_surface *rec, const rt_sphere *sp, const rt_ray *ray, double t);

/* Returns 1 and fills attenuation/scattered when the ray scatters, 0 when it
 * is absorbed. Asks smp for its numbers, after rt_sampler_bounce (which
 * ones: sampler.h's table). */
int rt_material_scatter(const rt_material *m, const rt_ray *in, const rt_surface *rec, rt_diffuse model,
                        rt_sampler *smp, rt_vec3 *attenuation, rt_ray *scattered);

#endif
