/* test_sphere.c - ray/sphere intersection: outside, inside, tangent, behind,
 * hollow (negative radius) normals. */
#include "check.h"
#include "material.h"
#include "sphere.h"

static int hit(rt_vec3 c, double r, rt_vec3 o, rt_vec3 d, double tmin, double tmax, double *t)
{
    rt_ray ray = {o, d};
    return rt_sphere_root(c, r * r, &ray, rt_v3_len2(d), tmin, t) && *t < tmax;
}

/* rt_sphere_closer over spheres[order[0..n)]: the index of the hit. */
static uint32_t closest_of(const rt_vec3 *centers, const int *order, int n, const rt_ray *ray, double *t)
{
    double closest = INFINITY;
    uint32_t best = UINT32_MAX;
    for (int i = 0; i < n; i++)
        rt_sphere_closer(centers[order[i]], 1.0, (uint32_t)order[i], ray, rt_v3_len2(ray->dir), 0.001, &closest,
                         &best);
    *t = closest;
    return best;
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

    /* The closest-hit rule: the nearest sphere, and of exact twins the lower
     * index, in whatever order they are tested. Spheres 0 and 2 are twins at
     * z = -5, sphere 1 is behind them, sphere 3 is beside the ray. */
    {
        const rt_vec3 centers[4] = {rt_v3(0, 0, -5), rt_v3(0, 0, -9), rt_v3(0, 0, -5), rt_v3(0, 5, -5)};
        const int orders[4][4] = {{0, 1, 2, 3}, {3, 2, 1, 0}, {2, 0, 3, 1}, {1, 3, 2, 0}};
        rt_ray ray = {rt_v3(0, 0, 0), rt_v3(0, 0, -1)};
        for (int k = 0; k < 4; k++) {
            double tk;
            CHECK_EQ_INT(closest_of(centers, orders[k], 4, &ray, &tk), 0);
            CHECK_NEAR(tk, 4, 1e-12);
        }
        const int no_twin[2] = {1, 2};
        double tk;
        CHECK_EQ_INT(closest_of(centers, no_twin, 2, &ray, &tk), 2); /* nearer than 1 */
        const int far_only[2] = {3, 1};
        CHECK_EQ_INT(closest_of(centers, far_only, 2, &ray, &tk), 1);
        CHECK_NEAR(tk, 8, 1e-12);
        double closest = 3.9;
        uint32_t best = UINT32_MAX;
        CHECK(!rt_sphere_closer(centers[0], 1.0, 0, &ray, 1.0, 0.001, &closest, &best)); /* beyond tmax */
        CHECK_EQ_INT(best, UINT32_MAX);
    }

    /* Normals face against the ray; hollow spheres flip outward. */
    rt_sphere solid = {.center = c, .radius = 1.0}, hollow = {.center = c, .radius = -1.0};
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
