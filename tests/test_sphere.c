/* test_sphere.c - ray/sphere intersection: outside, inside, tangent, behind,
 * hollow (negative radius) normals. */
#include "check.h"
#include "material.h"
#include "sphere.h"

static int hit(rt_vec3 c, double r, rt_vec3 o, rt_vec3 d, double tmin, double tmax, double *t)
{
    rt_ray ray = {o, d};
    return rt_sphere_intersect(c, r * r, &ray, rt_v3_len2(d), tmin, tmax, t);
}

int main(void)
{
    double t = -1;
    rt_vec3 c = rt_v3(0, 0, -5);
    /* From outside: near root. */
    CHECK(hit(c, 1, rt_v3(0, 0, 0), rt_v3(0, 0, -1), 0.001, INFINITY, &t));
    CHECK_NEAR(t, 4, 1e-12);
    /* Unnormalised direction: t in units of |dir|. */
    CHECK(hit(c, 1, rt_v3(0, 0, 0), rt_v3(0, 0, -2), 0.001, INFINITY, &t));
    CHECK_NEAR(t, 2, 1e-12);
    /* From inside: far root. */
    CHECK(hit(c, 1, rt_v3(0, 0, -5), rt_v3(0, 0, -1), 0.001, INFINITY, &t));
    CHECK_NEAR(t, 1, 1e-12);
    /* Sphere behind the ray: no hit. */
    CHECK(!hit(c, 1, rt_v3(0, 0, 0), rt_v3(0, 0, 1), 0.001, INFINITY, &t));
    /* Miss to the side. */
    CHECK(!hit(c, 1, rt_v3(0, 1.5, 0), rt_v3(0, 0, -1), 0.001, INFINITY, &t));
    /* Tangent: grazes at one point, t = 5. */
    CHECK(hit(c, 1, rt_v3(0, 1, 0), rt_v3(0, 0, -1), 0.001, INFINITY, &t));
    CHECK_NEAR(t, 5, 1e-6);
    /* tmax excludes a hit that is too far. */
    CHECK(!hit(c, 1, rt_v3(0, 0, 0), rt_v3(0, 0, -1), 0.001, 3.9, &t));
    /* tmin (shadow-acne bias) excludes the surface we start on. */
    CHECK(hit(c, 1, rt_v3(0, 0, -4), rt_v3(0, 0, -1), 0.001, INFINITY, &t));
    CHECK_NEAR(t, 2, 1e-12);
    /* The ground sphere of the final scene (radius 1000) at grazing height. */
    CHECK(hit(rt_v3(0, -1000, 0), 1000, rt_v3(13, 2, 3), rt_v3(-13, -2, -3), 0.001, INFINITY, &t));
    CHECK_NEAR(t, 1.0, 1e-6); /* touches the top of the ground at the origin */

    /* Normals face against the ray; hollow spheres flip outward. */
    rt_sphere solid = {c, 1.0, 0}, hollow = {c, -1.0, 0};
    rt_ray in = {rt_v3(0, 0, 0), rt_v3(0, 0, -1)};
    rt_surface s;
    rt_surface_from_sphere(&s, &solid, &in, 4.0);
    CHECK(s.front_face);
    CHECK_NEAR(s.normal.z, 1, 1e-12);
    rt_surface_from_sphere(&s, &hollow, &in, 4.0);
    CHECK(!s.front_face); /* outward normal of a hollow sphere points inward */
    CHECK_NEAR(s.normal.z, 1, 1e-12);
    CHECK_DONE();
}
