/* test_scenes.c - the named scenes: the list, each scene's spheres,
 * materials and camera as the book and seeds give them, and what the
 * camera sees at the centre of the image. */
#include <string.h>

#include "core_internal.h"
#include "accel.h"
#include "camera.h"
#include "check.h"
#include "scenes.h"
#include "status.h"

static void check_vec(rt_vec3 got, double x, double y, double z)
{
    CHECK_NEAR(got.x, x, 0);
    CHECK_NEAR(got.y, y, 0);
    CHECK_NEAR(got.z, z, 0);
}

/* Index of the sphere the ray through the image centre hits first, -1 for
 * sky; the lens sample comes from rng. */
static int centre_hit(const rt_scene *s, rt_rng *rng, double *t)
{
    rt_camera cam;
    rt_accel *a = NULL;
    if (rt_camera_init(&cam, &s->camera, 16.0 / 9.0) || rt_accel_new(&a, s, RT_ACCEL_BRUTE))
        return -2;
    rt_ray r = rt_camera_ray(&cam, 0.5, 0.5, rng);
    rt_hit h;
    int hit = rt_accel_closest(a, &r, 0.001, INFINITY, &h);
    rt_accel_free(a);
    *t = hit ? h.t * rt_v3_len(r.dir) : 0;
    return hit ? (int)h.prim : -1;
}

int main(void)
{
    /* The list: book 1's four scenes, book 2's nine and book 3's one, final
     * first, names unique, one line each; book 1's have no defaults of
     * their own. */
    CHECK_EQ_INT(rt_scenes_count(), 14);
    for (unsigned i = 0; i < rt_scenes_count(); i++)
        CHECK_EQ_INT(rt_scenes_info(i)->book, i < 4 ? 1 : i < 13 ? 2 : 3);
    CHECK(rt_scenes_info(rt_scenes_count()) == NULL);
    CHECK(!strcmp(rt_scenes_info(0)->name, "final"));
    for (unsigned i = 0; i < rt_scenes_count(); i++) {
        CHECK(strchr(rt_scenes_info(i)->summary, '\n') == NULL);
        for (unsigned j = 0; j < i; j++)
            CHECK(strcmp(rt_scenes_info(i)->name, rt_scenes_info(j)->name) != 0);
    }
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_named(&s, "nope", 42, 11, NULL), RT_EINVAL);
    CHECK_EQ_INT(rt_scene_build_named(&s, "Final", 42, 11, NULL), RT_EINVAL);

    /* final is rt_scene_build_final with the same seed and grid. */
    rt_scene f;
    CHECK_EQ_INT(rt_scene_build_named(&s, "final", 7, 3, NULL), RT_OK);
    CHECK_EQ_INT(rt_scene_build_final(&f, 7, 3), RT_OK);
    CHECK_EQ_U64(rt_scene_hash(&s), rt_scene_hash(&f));
    rt_scene_free(&s);
    rt_scene_free(&f);

    /* diffuse (seed 002): two grey spheres, default camera, vfov 90. */
    CHECK_EQ_INT(rt_scene_build_named(&s, "diffuse", 42, 11, NULL), RT_OK);
    CHECK_EQ_INT(s.n_spheres, 2);
    check_vec(s.spheres[0].center, 0, 0, -1);
    CHECK_NEAR(s.spheres[0].radius, 0.5, 0);
    check_vec(s.spheres[1].center, 0, -100.5, -1);
    CHECK_NEAR(s.spheres[1].radius, 100, 0);
    for (uint32_t i = 0; i < s.n_spheres; i++) {
        const rt_material *m = &s.materials[s.spheres[i].material];
        CHECK_EQ_INT(m->kind, RT_MAT_LAMBERTIAN);
        check_vec(m->albedo, 0.5, 0.5, 0.5);
    }
    check_vec(s.camera.lookfrom, 0, 0, 0);
    check_vec(s.camera.lookat, 0, 0, -1);
    check_vec(s.camera.vup, 0, 1, 0);
    CHECK_NEAR(s.camera.vfov_deg, 90, 0);
    CHECK_NEAR(s.camera.aperture, 0, 0);
    check_vec(s.sky_bottom, 1, 1, 1);
    check_vec(s.sky_top, 0.5, 0.7, 1.0);
    rt_rng rng = rt_rng_for_stream(3, RT_STREAM_TEST);
    double t;
    CHECK_EQ_INT(centre_hit(&s, &rng, &t), 0); /* straight ahead: the small sphere's front at z = -0.5 */
    CHECK_NEAR(t, 0.5, 1e-12);
    rt_scene_free(&s);

    /* materials (book ch. 10): ground, centre, glass with a hollow core
     * sharing its material, metal. */
    const double hollow[2] = {-0.4, -0.45};
    const char *names[2] = {"materials", "defocus"};
    for (int k = 0; k < 2; k++) {
        CHECK_EQ_INT(rt_scene_build_named(&s, names[k], 42, 11, NULL), RT_OK);
        CHECK_EQ_INT(s.n_spheres, 5);
        const rt_sphere *sp = s.spheres;
        const rt_material *mat = s.materials;
        check_vec(sp[0].center, 0, -100.5, -1);
        CHECK_NEAR(sp[0].radius, 100, 0);
        CHECK_EQ_INT(mat[sp[0].material].kind, RT_MAT_LAMBERTIAN);
        check_vec(mat[sp[0].material].albedo, 0.8, 0.8, 0.0);
        check_vec(sp[1].center, 0, 0, -1);
        CHECK_EQ_INT(mat[sp[1].material].kind, RT_MAT_LAMBERTIAN);
        check_vec(mat[sp[1].material].albedo, 0.1, 0.2, 0.5);
        check_vec(sp[2].center, -1, 0, -1);
        CHECK_NEAR(sp[2].radius, 0.5, 0);
        check_vec(sp[3].center, -1, 0, -1);
        CHECK_NEAR(sp[3].radius, hollow[k], 0);
        CHECK_EQ_INT(sp[2].material, sp[3].material);
        CHECK_EQ_INT(mat[sp[2].material].kind, RT_MAT_DIELECTRIC);
        CHECK_NEAR(mat[sp[2].material].ior, 1.5, 0);
        check_vec(sp[4].center, 1, 0, -1);
        CHECK_EQ_INT(mat[sp[4].material].kind, RT_MAT_METAL);
        check_vec(mat[sp[4].material].albedo, 0.8, 0.6, 0.2);
        CHECK_NEAR(mat[sp[4].material].fuzz, 0, 0);
        if (k == 0) {
            check_vec(s.camera.lookfrom, 0, 0, 0);
            CHECK_NEAR(s.camera.vfov_deg, 90, 0);
            CHECK_NEAR(s.camera.aperture, 0, 0);
        } else {
            /* defocus (book ch. 12): from (3,3,2) at (0,0,-1), focused on
             * lookat. Every lens sample's centre ray passes through the
             * focus point, the centre of the blue sphere: all hit it. */
            check_vec(s.camera.lookfrom, 3, 3, 2);
            check_vec(s.camera.lookat, 0, 0, -1);
            CHECK_NEAR(s.camera.vfov_deg, 20, 0);
            CHECK_NEAR(s.camera.aperture, 2.0, 0);
            CHECK_NEAR(s.camera.focus_dist, sqrt(27.0), 1e-15);
            int all_centre = 1;
            for (int i = 0; i < 100; i++)
                all_centre &= centre_hit(&s, &rng, &t) == 1;
            CHECK(all_centre);
        }
        rt_scene_free(&s);
    }
    /* bouncing-spheres: the first small sphere's centre is the scene
     * stream's second and third numbers as z, then x, whatever the compiler
     * (scenes_book2.c: the order of a call's arguments is open in C) */
    CHECK_EQ_INT(rt_scene_build_named(&s, "bouncing-spheres", 42, 11, NULL), RT_OK);
    rt_rng sr = rt_rng_for_stream(42, RT_STREAM_SCENE);
    const double choose = rt_rng_double(&sr), cz = -11 + 0.9 * rt_rng_double(&sr), cx = -11 + 0.9 * rt_rng_double(&sr);
    check_vec(choose < 0.8 ? s.shapes.movers.items[0].center0 : s.spheres[1].center, cx, 0.2, cz);
    rt_scene_free(&s);
    CHECK_DONE();
}
