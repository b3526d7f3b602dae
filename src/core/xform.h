/* xform.h - rigid motions of book 2's instances (a rotation, then a
 * translation), applied when a scene is built: an instance's spheres,
 * quads, moving spheres and media are stored in world space, which is exact
 * for these shapes (a rotated quad is a quad, a rotated sphere a sphere).
 * Header-only. */
#ifndef RT_XFORM_H
#define RT_XFORM_H

#include <math.h>

#include "vec.h"

/* p -> R p + t, R's rows in row[]. */
typedef struct rt_xform {
    rt_vec3 row[3];
    rt_vec3 t;
} rt_xform;

static inline rt_xform rt_xform_identity(void)
{
    rt_xform x = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {0, 0, 0}};
    return x;
}

/* The book's rotate_y by deg degrees: x' = cos x + sin z, z' = -sin x + cos z. */
static inline rt_xform rt_xform_rotate_y(double deg)
{
    const double a = deg * (3.14159265358979323846 / 180.0), c = cos(a), s = sin(a);
    rt_xform x = {{{c, 0, s}, {0, 1, 0}, {-s, 0, c}}, {0, 0, 0}};
    return x;
}

static inline rt_xform rt_xform_translate(rt_vec3 t)
{
    rt_xform x = rt_xform_identity();
    x.t = t;
    return x;
}

static inline rt_vec3 rt_xform_vector(const rt_xform *x, rt_vec3 v)
{
    return rt_v3(rt_v3_dot(x->row[0], v), rt_v3_dot(x->row[1], v), rt_v3_dot(x->row[2], v));
}

static inline rt_vec3 rt_xform_point(const rt_xform *x, rt_vec3 p)
{
    return rt_v3_add(rt_xform_vector(x, p), x->t);
}

/* `outer` after `inner`: p -> outer(inner(p)). */
static inline rt_xform rt_xform_then(const rt_xform *inner, const rt_xform *outer)
{
    rt_xform x;
    for (int i = 0; i < 3; i++) {
        const rt_vec3 r = outer->row[i];
        x.row[i] = rt_v3(r.x * inner->row[0].x + r.y * inner->row[1].x + r.z * inner->row[2].x,
                         r.x * inner->row[0].y + r.y * inner->row[1].y + r.z * inner->row[2].y,
                         r.x * inner->row[0].z + r.y * inner->row[1].z + r.z * inner->row[2].z);
    }
    x.t = rt_xform_point(outer, inner->t);
    return x;
}

/* 1 when x is the identity (no rotation: nothing for a sphere's frame). */
static inline int rt_xform_no_rotation(const rt_xform *x)
{
    return x->row[0].x == 1 && x->row[0].y == 0 && x->row[0].z == 0 && x->row[1].x == 0 && x->row[1].y == 1 &&
           x->row[1].z == 0 && x->row[2].x == 0 && x->row[2].y == 0 && x->row[2].z == 1;
}

#endif
