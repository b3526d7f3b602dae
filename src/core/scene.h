/* scene.h - the scene description every rank renders: spheres, materials,
 * camera and background; building the book's scenes from a seed; and the
 * versioned, endian-independent byte format rank 0 broadcasts. */
#ifndef RT_SCENE_H
#define RT_SCENE_H

#include <stddef.h>
#include <stdint.h>

#include "vec.h"

typedef enum rt_material_kind {
    RT_MAT_LAMBERTIAN = 0,
    RT_MAT_METAL = 1,
    RT_MAT_DIELECTRIC = 2,
} rt_material_kind;

typedef struct rt_material {
    uint32_t kind;  /* rt_material_kind */
    rt_vec3 albedo; /* lambertian and metal */
    double fuzz;    /* metal, in [0, 1] */
    double ior;     /* dielectric index of refraction */
} rt_material;

/* A negative radius keeps the geometry of |radius| but flips the normal:
 * the book's hollow glass sphere. */
typedef struct rt_sphere {
    rt_vec3 center;
    double radius;
    uint32_t material;
} rt_sphere;

typedef struct rt_camera_desc {
    rt_vec3 lookfrom, lookat, vup;
    double vfov_deg;   /* vertical field of view */
    double aperture;   /* lens diameter; 0 = pinhole */
    double focus_dist; /* distance to the plane in focus */
} rt_camera_desc;

typedef struct rt_scene {
    rt_sphere *spheres;
    uint32_t n_spheres;
    size_t cap_spheres;
    rt_material *materials;
    uint32_t n_materials;
    size_t cap_materials;
    rt_camera_desc camera;
    rt_vec3 sky_bottom, sky_top; /* background gradient by ray direction y */
} rt_scene;

#define RT_SCENE_FORMAT_VERSION 1u
#define RT_SCENE_MAX_SPHERES 10000000u

void rt_scene_init(rt_scene *s);
void rt_scene_free(rt_scene *s);
/* Appends a material; *index receives its index. */
int rt_scene_add_material(rt_scene *s, const rt_material *m, uint32_t *index);
int rt_scene_add_sphere(rt_scene *s, rt_vec3 center, double radius, uint32_t material);
/* Appends material m and a sphere that uses it. */
int rt_scene_add(rt_scene *s, rt_vec3 center, double radius, rt_material m);

/* The book's materials. Fields a kind does not use get fixed values, so
 * every builder and the scene-file loader produce the same bytes for the
 * same material. Metal fuzz is clamped to at most 1 as in the book. */
rt_material rt_scene_lambertian(rt_vec3 albedo);
rt_material rt_scene_metal(rt_vec3 albedo, double fuzz);
rt_material rt_scene_dielectric(double ior);

/* The book 1 final scene as seed 000's renderer builds it: ground, a
 * 2grid x 2grid field of small spheres (80/15/5 % lambertian/metal/glass)
 * drawn from the seed's scene stream, and the three large spheres. */
int rt_scene_build_final(rt_scene *s, uint64_t seed, int grid);

/* Serialized form: magic "RTSCENE\0", u32 version, u32 counts, every double
 * as IEEE-754 bits in little endian, then a 64-bit checksum of all that
 * precedes it. serialize -> deserialize -> serialize is byte-identical. */
int rt_scene_serialize(const rt_scene *s, uint8_t **buf, size_t *len);
int rt_scene_deserialize(rt_scene *s, const uint8_t *buf, size_t len);

#endif
