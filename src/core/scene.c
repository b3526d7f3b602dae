/* scene.c - scene construction, the book's final scene, and the byte format. */
#include "scene.h"
#include "core_internal.h"

#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "hash.h"
#include "rng.h"
#include "status.h"

void rt_scene_init(rt_scene *s)
{
    memset(s, 0, sizeof *s);
    s->sky_bottom = rt_v3(1.0, 1.0, 1.0);
    s->sky_top = rt_v3(0.5, 0.7, 1.0);
    s->camera.vup = rt_v3(0, 1, 0);
    s->camera.vfov_deg = 90.0;
    s->camera.focus_dist = 1.0;
    s->camera.lookat = rt_v3(0, 0, -1);
}

void rt_scene_free(rt_scene *s)
{
    free(s->spheres);
    free(s->materials);
    free(s->shapes.quads.items);
    free(s->shapes.movers.items);
    free(s->shapes.frames.items);
    free(s->media.media.items);
    free(s->media.hull.items);
    free(s->tex.textures.items);
    free(s->tex.images.items);
    free(s->tex.texels);
    free(s->keys.items);
    memset(s, 0, sizeof *s);
}

/* Room for one more element, within the scene format's limit. */
static int grow(void **p, size_t *cap, uint32_t n, size_t elem)
{
    return n >= RT_SCENE_MAX_SPHERES ? RT_EOVERFLOW : rt_array_reserve(p, cap, (size_t)n + 1, elem);
}

int rt_scene_add_material(rt_scene *s, const rt_material *m, uint32_t *index)
{
    int st = grow((void **)&s->materials, &s->cap_materials, s->n_materials, sizeof *m);
    if (st)
        return st;
    s->materials[s->n_materials] = *m;
    if (index)
        *index = s->n_materials;
    s->n_materials++;
    return RT_OK;
}

int rt_scene_add_sphere(rt_scene *s, rt_vec3 center, double radius, uint32_t material)
{
    if (material >= s->n_materials || !(radius != 0.0) || !isfinite(radius))
        return RT_EINVAL;
    int st = grow((void **)&s->spheres, &s->cap_spheres, s->n_spheres, sizeof *s->spheres);
    if (st)
        return st;
    rt_sphere *sp = &s->spheres[s->n_spheres++];
    sp->center = center;
    sp->radius = radius;
    sp->material = material;
    sp->frame = 0;
    return RT_OK;
}

int rt_scene_add(rt_scene *s, rt_vec3 c, double r, rt_material m)
{
    uint32_t idx;
    int st = rt_scene_add_material(s, &m, &idx);
    return st ? st : rt_scene_add_sphere(s, c, r, idx);
}

rt_material rt_scene_lambertian(rt_vec3 albedo)
{
    rt_material m = {.kind = RT_MAT_LAMBERTIAN, .albedo = albedo, .fuzz = 0.0, .ior = 1.0};
    return m;
}
rt_material rt_scene_metal(rt_vec3 albedo, double fuzz)
{
    rt_material m = {.kind = RT_MAT_METAL, .albedo = albedo, .fuzz = fuzz < 1.0 ? fuzz : 1.0, .ior = 1.0};
    return m;
}
rt_material rt_scene_dielectric(double ior)
{
    rt_material m = {.kind = RT_MAT_DIELECTRIC, .albedo = rt_v3(1, 1, 1), .fuzz = 0.0, .ior = ior};
    return m;
}

int rt_scene_build_final(rt_scene *s, uint64_t seed, int grid)
{
    if (grid < 0 || grid > 1000)
        return RT_EINVAL;
    rt_scene_init(s);
    rt_rng rng = rt_rng_for_stream(seed, RT_STREAM_SCENE);
    int st = rt_scene_add(s, rt_v3(0, -1000, 0), 1000, rt_scene_lambertian(rt_v3(0.5, 0.5, 0.5)));
    const rt_vec3 focal[3] = {{4, 0.2, 0}, {0, 1, 0}, {-4, 0.2, 0}};
    for (int a = -grid; a < grid && !st; a++) {
        for (int b = -grid; b < grid && !st; b++) {
            /* Draw order follows the seed renderer: material choice, then x, z. */
            double choose = rt_rng_double(&rng);
            double cx = a + 0.9 * rt_rng_double(&rng);
            double cz = b + 0.9 * rt_rng_double(&rng);
            rt_vec3 c = rt_v3(cx, 0.2, cz);
            if (rt_v3_len(rt_v3_sub(c, focal[0])) <= 0.9 || rt_v3_len(rt_v3_sub(c, focal[1])) <= 0.9 ||
                rt_v3_len(rt_v3_sub(c, focal[2])) <= 0.9)
                continue;
            if (choose < 0.8) {
                double r = rt_rng_double(&rng) * rt_rng_double(&rng);
                double g = rt_rng_double(&rng) * rt_rng_double(&rng);
                double bl = rt_rng_double(&rng) * rt_rng_double(&rng);
                st = rt_scene_add(s, c, 0.2, rt_scene_lambertian(rt_v3(r, g, bl)));
            } else if (choose < 0.95) {
                double r = rt_rng_range(&rng, 0.5, 1.0);
                double g = rt_rng_range(&rng, 0.5, 1.0);
                double bl = rt_rng_range(&rng, 0.5, 1.0);
                double fuzz = rt_rng_range(&rng, 0.0, 0.5);
                st = rt_scene_add(s, c, 0.2, rt_scene_metal(rt_v3(r, g, bl), fuzz));
            } else {
                st = rt_scene_add(s, c, 0.2, rt_scene_dielectric(1.5));
            }
        }
    }
    if (!st)
        st = rt_scene_add(s, rt_v3(-4, 1, 0), 1.0, rt_scene_lambertian(rt_v3(0.4, 0.2, 0.1)));
    if (!st)
        st = rt_scene_add(s, rt_v3(0, 1, 0), 1.0, rt_scene_dielectric(1.5));
    if (!st)
        st = rt_scene_add(s, rt_v3(4, 1, 0), 1.0, rt_scene_metal(rt_v3(0.7, 0.6, 0.5), 0.0));
    s->camera.lookfrom = rt_v3(13, 2, 3);
    s->camera.lookat = rt_v3(0, 0, 0);
    s->camera.vup = rt_v3(0, 1, 0);
    s->camera.vfov_deg = 20.0;
    s->camera.aperture = 0.1;
    s->camera.focus_dist = 10.0;
    if (st)
        rt_scene_free(s);
    return st;
}
