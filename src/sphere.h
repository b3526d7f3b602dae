/* sphere.h - ray/sphere intersection in double precision, shared by every
 * intersector (brute force, BVH, Embree refinement) so that all of them
 * agree on t to the last bit. */
#ifndef RT_SPHERE_H
#define RT_SPHERE_H

#include "vec.h"

/* Nearest root of |orig + t dir - center|^2 = r2 with tmin < t < tmax.
 * Returns 1 and stores t on a hit. Same arithmetic as the book
 * (half-b form) so brute force reproduces the reference renderer. */
static inline int rt_sphere_intersect(rt_vec3 center, double r2, const rt_ray *ray, double a, double tmin,
                                      double tmax, double *t)
{
    rt_vec3 oc = rt_v3_sub(ray->orig, center);
    double half_b = rt_v3_dot(oc, ray->dir);
    double c = rt_v3_dot(oc, oc) - r2;
    double disc = half_b * half_b - a * c;
    if (disc < 0.0)
        return 0;
    /* Range checks on root * a: the division is paid only for a hit. */
    double sq = sqrt(disc), lo = tmin * a, hi = tmax * a;
    double num = -half_b - sq;
    if (num <= lo || num >= hi) {
        num = -half_b + sq;
        if (num <= lo || num >= hi)
            return 0;
    }
    *t = num / a;
    return 1;
}

#endif
