/* vec.h - 3-component double vector math, header-only so the compiler can
 * keep everything in registers on the hot path. */
#ifndef RT_VEC_H
#define RT_VEC_H

#include <math.h>

typedef struct rt_vec3 {
    double x, y, z;
} rt_vec3;

static inline rt_vec3 rt_v3(double x, double y, double z)
{
    rt_vec3 v = {x, y, z};
    return v;
}
static inline rt_vec3 rt_v3_add(rt_vec3 a, rt_vec3 b) { return rt_v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline rt_vec3 rt_v3_sub(rt_vec3 a, rt_vec3 b) { return rt_v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline rt_vec3 rt_v3_mul(rt_vec3 a, rt_vec3 b) { return rt_v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline rt_vec3 rt_v3_scale(rt_vec3 a, double s) { return rt_v3(a.x * s, a.y * s, a.z * s); }
static inline rt_vec3 rt_v3_neg(rt_vec3 a) { return rt_v3(-a.x, -a.y, -a.z); }
static inline double rt_v3_dot(rt_vec3 a, rt_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline double rt_v3_len2(rt_vec3 a) { return rt_v3_dot(a, a); }
static inline double rt_v3_len(rt_vec3 a) { return sqrt(rt_v3_dot(a, a)); }
static inline rt_vec3 rt_v3_cross(rt_vec3 a, rt_vec3 b)
{
    return rt_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline rt_vec3 rt_v3_unit(rt_vec3 a) { return rt_v3_scale(a, 1.0 / rt_v3_len(a)); }
/* a + s*b, written out so it never becomes a fused multiply-add by accident
 * (we build with -ffp-contract=off; images must match across CPUs). */
static inline rt_vec3 rt_v3_madd(rt_vec3 a, rt_vec3 b, double s)
{
    return rt_v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s);
}
static inline int rt_v3_near_zero(rt_vec3 a)
{
    const double e = 1e-8;
    return fabs(a.x) < e && fabs(a.y) < e && fabs(a.z) < e;
}
/* Mirror reflection of v about unit normal n. */
static inline rt_vec3 rt_v3_reflect(rt_vec3 v, rt_vec3 n)
{
    return rt_v3_sub(v, rt_v3_scale(n, 2.0 * rt_v3_dot(v, n)));
}

typedef struct rt_ray {
    rt_vec3 orig, dir;
} rt_ray;

static inline rt_vec3 rt_ray_at(const rt_ray *r, double t) { return rt_v3_madd(r->orig, r->dir, t); }

#endif
