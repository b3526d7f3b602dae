/* scenes.c - the named scenes: book 1's final scene and the chapter scenes
 * (diffuse chapter's two spheres, the three-material scene with a hollow
 * glass sphere, and its defocus-blur view). */
#include "scenes.h"

#include <string.h>

#include "scenes_book2.h"
#include "status.h"

static const rt_scene_info SCENES[] = {
    {"final", "book 1 final scene: random small spheres around three large ones (--seed, --grid)", 1, 0, 0, 0, 0, 0},
    {"diffuse", "diffuse chapter (seed 002): grey sphere on a grey ground, camera at the origin, vfov 90", 1, 0, 0, 0, 0, 0},
    {"materials", "book 1 ch. 10: lambertian centre, hollow glass left, metal right, yellow-green ground", 1, 0, 0, 0, 0, 0},
    {"defocus", "book 1 ch. 12: the materials scene from (3,3,2) with vfov 20, aperture 2 (defocus blur)", 1, 0, 0, 0, 0, 0},
    {"bouncing-spheres", "book 2 ch. 2: book 1's final scene with moving (motion-blurred) spheres on a checker",
     2, 400, 225, 100, 50, 0},
    {"checkered-spheres", "book 2 ch. 4: two checkered spheres", 2, 400, 225, 100, 50, 0},
    {"earth", "book 2 ch. 4: the earth, an image texture (earthmap.jpg, --texture-dir)", 2, 400, 225, 100, 50, 1},
    {"perlin-spheres", "book 2 ch. 5: two marble (Perlin noise) spheres", 2, 400, 225, 100, 50, 0},
    {"quads", "book 2 ch. 6: five coloured quads", 2, 400, 400, 100, 50, 0},
    {"simple-light", "book 2 ch. 7: the marble spheres lit by a sphere and a quad light, black sky", 2, 400, 225, 100,
     50, 0},
    {"cornell-box", "book 2 ch. 7-8: the Cornell box with two rotated boxes", 2, 600, 600, 200, 50, 0},
    {"cornell-smoke", "book 2 ch. 9: the Cornell box with boxes of black and white smoke", 2, 600, 600, 200, 50, 0},
    {"book2-final", "book 2 ch. 10: boxes, lights, fog, glass, the earth, marble and instanced spheres (--seed)", 2,
     800, 800, 10000, 40, 1},
    {"book3-final", "book 3: the Cornell box with a rotated box, a glass sphere and a light that emits downward only",
     3, 600, 600, 100, 50, 0},
};
#define N_SCENES (sizeof SCENES / sizeof SCENES[0])

unsigned rt_scenes_count(void) { return (unsigned)N_SCENES; }

const rt_scene_info *rt_scenes_info(unsigned i) { return i < N_SCENES ? &SCENES[i] : NULL; }

const rt_scene_info *rt_scenes_find(const char *name)
{
    for (unsigned i = 0; i < N_SCENES; i++)
        if (!strcmp(name, SCENES[i].name))
            return &SCENES[i];
    return NULL;
}

/* Seed 002: both spheres absorb half the light (the chapter's 0.5 factor);
 * the camera is the book's default one (origin, looking down -z, viewport 2
 * high at focal length 1 = vfov 90). */
static int build_diffuse(rt_scene *s)
{
    rt_material grey = rt_scene_lambertian(rt_v3(0.5, 0.5, 0.5));
    int st = rt_scene_add(s, rt_v3(0, 0, -1), 0.5, grey);
    return st ? st : rt_scene_add(s, rt_v3(0, -100.5, -1), 100, grey);
}

/* Book 1 (v3.2.3) ch. 10-12. One glass material serves the outer sphere and
 * the hollow inner one, as in the book; inner radius -0.4 in ch. 10, -0.45
 * from ch. 11 on. */
static int build_materials(rt_scene *s, double hollow_radius)
{
    rt_material ground = rt_scene_lambertian(rt_v3(0.8, 0.8, 0.0));
    rt_material center = rt_scene_lambertian(rt_v3(0.1, 0.2, 0.5));
    rt_material left = rt_scene_dielectric(1.5);
    rt_material right = rt_scene_metal(rt_v3(0.8, 0.6, 0.2), 0.0);
    uint32_t glass;
    int st = rt_scene_add(s, rt_v3(0, -100.5, -1), 100, ground);
    if (!st)
        st = rt_scene_add(s, rt_v3(0, 0, -1), 0.5, center);
    if (!st)
        st = rt_scene_add_material(s, &left, &glass);
    if (!st)
        st = rt_scene_add_sphere(s, rt_v3(-1, 0, -1), 0.5, glass);
    if (!st)
        st = rt_scene_add_sphere(s, rt_v3(-1, 0, -1), hollow_radius, glass);
    return st ? st : rt_scene_add(s, rt_v3(1, 0, -1), 0.5, right);
}

int rt_scene_build_named(rt_scene *s, const char *name, uint64_t seed, int grid, const rt_scene_image *img)
{
    if (!strcmp(name, "final"))
        return rt_scene_build_final(s, seed, grid);
    for (unsigned i = 0; i < N_SCENES; i++)
        if (SCENES[i].book >= 2 && !strcmp(name, SCENES[i].name))
            return rt_scenes_book2_build(s, name, seed, img);
    rt_scene_init(s); /* camera: origin looking down -z, vfov 90, pinhole */
    int st;
    if (!strcmp(name, "diffuse")) {
        st = build_diffuse(s);
    } else if (!strcmp(name, "materials")) {
        st = build_materials(s, -0.4);
    } else if (!strcmp(name, "defocus")) {
        st = build_materials(s, -0.45);
        rt_camera_desc *c = &s->camera;
        c->lookfrom = rt_v3(3, 3, 2);
        c->lookat = rt_v3(0, 0, -1);
        c->vup = rt_v3(0, 1, 0);
        c->vfov_deg = 20.0;
        c->aperture = 2.0;
        c->focus_dist = rt_v3_len(rt_v3_sub(c->lookfrom, c->lookat));
    } else {
        return RT_EINVAL;
    }
    if (st)
        rt_scene_free(s);
    return st;
}
