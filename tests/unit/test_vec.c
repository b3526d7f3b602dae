/* test_vec.c - vector math. */
#include "check.h"
#include "vec.h"

int main(void)
{
    rt_vec3 a = rt_v3(1, 2, 3), b = rt_v3(-4, 5, 0.5);
    CHECK_NEAR(rt_v3_dot(a, b), -4 + 10 + 1.5, 0);
    rt_vec3 c = rt_v3_cross(a, b);
    CHECK_NEAR(c.x, 2 * 0.5 - 3 * 5, 0);
    CHECK_NEAR(c.y, 3 * -4 - 1 * 0.5, 0);
    CHECK_NEAR(c.z, 1 * 5 - 2 * -4, 0);
    CHECK_NEAR(rt_v3_dot(c, a), 0, 1e-12);
    CHECK_NEAR(rt_v3_dot(c, b), 0, 1e-12);
    CHECK_NEAR(rt_v3_len(rt_v3(3, 4, 12)), 13, 0);
    rt_vec3 u = rt_v3_unit(rt_v3(0, 0, -7));
    CHECK_NEAR(u.z, -1, 0);
    rt_vec3 m = rt_v3_madd(a, b, 2);
    CHECK_NEAR(m.x, -7, 0);
    CHECK_NEAR(m.y, 12, 0);
    CHECK_NEAR(m.z, 4, 0);
    /* Reflection keeps length and mirrors the normal component. */
    rt_vec3 r = rt_v3_reflect(rt_v3(1, -1, 0), rt_v3(0, 1, 0));
    CHECK_NEAR(r.x, 1, 0);
    CHECK_NEAR(r.y, 1, 0);
    CHECK(rt_v3_near_zero(rt_v3(1e-9, -1e-9, 0)));
    CHECK(!rt_v3_near_zero(rt_v3(1e-7, 0, 0)));
    rt_ray ray = {rt_v3(1, 1, 1), rt_v3(0, 2, 0)};
    rt_vec3 p = rt_ray_at(&ray, 1.5);
    CHECK_NEAR(p.y, 4, 0);
    CHECK_DONE();
}
