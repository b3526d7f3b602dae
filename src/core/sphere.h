/* sphere.h - ray/sphere intersection in double precision and the rule that
 * picks the closest hit, shared by every intersector (brute force, BVH,
 * Embree refinement) so that all of them agree on the sphere and on t to the
 * last bit. */
#ifndef RT_SPHERE_H
#define RT_SPHERE_H

#include <stdint.h>

#include "vec.h"

/* The first root t > tmin of |orig + t dir - center|^2 = r2 (in units of
 * |dir|, with a = |dir|^2): the near one unless it is at or below tmin, then
 * the far one. Returns 1 and stores t when there is one. Same arithmetic as
 * the book (half-b form), in the same order everywhere: brute force, the
 * BVH and the ray packets (bvh.c's sphere_x4, lane by lane) get the same
 * bits. */
static inline int rt_sphere_root(rt_vec3 center, double r2, const rt_ray *ray, double a, double tmin, double *t)
{
    rt_vec3 oc = rt_v3_sub(ray->orig, center);
    double half_b = rt_v3_dot(oc, ray->dir);
    double c = rt_v3_dot(oc, oc) - r2;
    double disc = half_b * half_b - a * c;
    if (disc < 0.0)
        return 0;
    double sq = sqrt(disc), lo = tmin * a;
    double num = -half_b - sq;
    if (num <= lo) {
        num = -half_b + sq;
        if (num <= lo)
            return 0;
    }
    *t = num / a;
    return 1;
}

/* The closest-hit rule of every intersector, which makes its answer
 * independent of the order in which it tests spheres: sphere `index`
 * (center, r2) replaces the hit so far (*closest, *best) when its root
 * (rt_sphere_root) is nearer, or exactly as near with a lower index; returns
 * 1 if it does. After any sequence of tests the hit is the least (t, index)
 * over the spheres tested, the same for brute force, every BVH traversal
 * and ray packets. Start with *closest = tmax (a hit at tmax itself counts)
 * and *best = UINT32_MAX. */
static inline int rt_sphere_closer(rt_vec3 center, double r2, uint32_t index, const rt_ray *ray, double a,
                                   double tmin, double *closest, uint32_t *best)
{
    double t;
    if (!rt_sphere_root(center, r2, ray, a, tmin, &t))
        return 0;
    if (t < *closest || (t == *closest && index < *best)) {
        *closest = t;
        *best = index;
        return 1;
    }
    return 0;
}

#endif
