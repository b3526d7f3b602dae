/* test_material.c - metal reflection angle, dielectric total internal
 * reflection, attenuation never above 1, diffuse directions above the
 * surface. */
#include "check.h"
#include "material.h"
#include "rng.h"

int main(void)
{
    rt_rng rng = rt_rng_for_stream(1, RT_STREAM_TEST);
    rt_surface s = {rt_v3(0, 0, 0), rt_v3(0, 1, 0), 1.0, 1};
    rt_vec3 att;
    rt_ray out;

    /* Mirror metal: angle of reflection equals angle of incidence. */
    rt_material mirror = {RT_MAT_METAL, rt_v3(0.7, 0.6, 0.5), 0.0, 1.0};
    rt_ray in = {rt_v3(-1, 1, 0), rt_v3(1, -1, 0)};
    CHECK(rt_material_scatter(&mirror, &in, &s, RT_DIFFUSE_LAMBERTIAN, &rng, &att, &out));
    rt_vec3 d = rt_v3_unit(out.dir);
    CHECK_NEAR(d.x, 1 / sqrt(2.0), 1e-12);
    CHECK_NEAR(d.y, 1 / sqrt(2.0), 1e-12);
    CHECK_NEAR(d.z, 0, 1e-12);
    CHECK_NEAR(att.x, 0.7, 0);

    /* Glass from inside at a grazing angle: total internal reflection,
     * always (no random choice involved). */
    rt_material glass = {RT_MAT_DIELECTRIC, rt_v3(1, 1, 1), 0.0, 1.5};
    rt_surface inside = {rt_v3(0, 0, 0), rt_v3(0, -1, 0), 1.0, 0};
    rt_ray graze = {rt_v3(-1, -0.2, 0), rt_v3(1, 0.2, 0)};
    int tir = 1;
    for (int i = 0; i < 1000; i++) {
        CHECK(rt_material_scatter(&glass, &graze, &inside, RT_DIFFUSE_LAMBERTIAN, &rng, &att, &out));
        tir &= out.dir.y < 0 && fabs(out.dir.x - rt_v3_unit(graze.dir).x) < 1e-12;
    }
    CHECK(tir);
    /* Head-on into glass: mostly refracts straight through (R0 = 4 %). */
    rt_ray head = {rt_v3(0, 1, 0), rt_v3(0, -1, 0)};
    int through = 0;
    for (int i = 0; i < 10000; i++) {
        rt_material_scatter(&glass, &head, &s, RT_DIFFUSE_LAMBERTIAN, &rng, &att, &out);
        through += out.dir.y < 0;
    }
    CHECK_NEAR(through / 10000.0, 0.96, 0.01);
    CHECK_NEAR(rt_material_reflectance(1.0, 1.0 / 1.5), 0.04, 1e-12);
    CHECK_NEAR(rt_material_reflectance(0.0, 1.5), 1.0, 1e-12);

    /* Attenuation never above 1 and diffuse directions stay above the
     * surface for every model and a random set of materials. */
    int ok_att = 1, ok_dir = 1;
    for (int i = 0; i < 20000; i++) {
        rt_material m;
        m.kind = (uint32_t)(i % 3);
        m.albedo = rt_v3(rt_rng_double(&rng), rt_rng_double(&rng), rt_rng_double(&rng));
        m.fuzz = 0.5 * rt_rng_double(&rng);
        m.ior = 1.0 + rt_rng_double(&rng);
        rt_ray r = {rt_v3(0, 1, 0), rt_v3(rt_rng_double(&rng) - 0.5, -1, rt_rng_double(&rng) - 0.5)};
        rt_diffuse model = (rt_diffuse)(i / 3 % 3);
        if (rt_material_scatter(&m, &r, &s, model, &rng, &att, &out)) {
            ok_att &= att.x <= 1 && att.y <= 1 && att.z <= 1 && att.x >= 0 && att.y >= 0 && att.z >= 0;
            if (m.kind == RT_MAT_LAMBERTIAN)
                ok_dir &= rt_v3_dot(out.dir, s.normal) >= 0;
            if (m.kind == RT_MAT_METAL)
                ok_dir &= rt_v3_dot(out.dir, s.normal) > 0;
        }
    }
    CHECK(ok_att);
    CHECK(ok_dir);
    CHECK_DONE();
}
