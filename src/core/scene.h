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
    RT_MAT_EMITTER = 3,   /* book 2's diffuse_light: emits, never scatters */
    RT_MAT_ISOTROPIC = 4, /* a medium's phase function: uniform over the sphere */
} rt_material_kind;

/* rt_material.flags */
#define RT_MAT_TWO_SIDED 1u /* an emitter that emits from both faces (book 2); else the front face only (book 3) */

typedef struct rt_material {
    uint32_t kind;  /* rt_material_kind */
    rt_vec3 albedo; /* lambertian, metal, isotropic: the colour when texture is 0 */
    double fuzz;    /* metal, in [0, 1] */
    double ior;     /* dielectric index of refraction */
    uint32_t texture; /* lambertian, isotropic, emitter: 0 none, else 1 + index into tex.textures */
    uint32_t flags;   /* RT_MAT_* flags */
    rt_vec3 emit;     /* emitter: radiance when texture is 0 (else the texture's value) */
} rt_material;

/* A negative radius keeps the geometry of |radius| but flips the normal:
 * the book's hollow glass sphere. frame: 0, or 1 + the index of the
 * rotation (shapes.frames) its (u, v) are taken in: a sphere of a rotated instance
 * keeps the texture it had before the rotation. Spatial textures (checker,
 * noise) are evaluated at the world-space hit point, as the book does. */
typedef struct rt_sphere {
    rt_vec3 center;
    double radius;
    uint32_t material;
    uint32_t frame;
} rt_sphere;

/* ---- book 2: shapes, textures, media ------------------------------------- *
 * Instances (translations, rotations about y, and any rigid motion with a
 * uniform scale) are flattened when the scene is built: their spheres,
 * quads and moving spheres are stored in world space, which is exact for
 * these shapes (a rotated quad is a quad, a rotated sphere a sphere). */

/* The book's quad: the parallelogram q + a u + b v, a and b in [0, 1];
 * its normal is unit(u x v) (the front face), its (u, v) are (a, b).
 * A box is six of them. */
typedef struct rt_quad {
    rt_vec3 q, u, v;
    uint32_t material;
} rt_quad;

/* A sphere whose centre moves from center0 at time 0 to center1 at time 1
 * (linear in the ray's time, which is in [0, 1)). */
typedef struct rt_mover {
    rt_vec3 center0, center1;
    double radius;
    uint32_t material;
    uint32_t frame; /* as rt_sphere's */
} rt_mover;

/* A rotation, world to object: row k is object axis k in world space. */
typedef struct rt_frame {
    rt_vec3 row[3];
} rt_frame;

typedef enum rt_texture_kind {
    RT_TEX_SOLID = 0,   /* color */
    RT_TEX_CHECKER = 1, /* the book's spatial checker: cells of size scale, textures even and odd */
    RT_TEX_NOISE = 2,   /* Perlin noise at frequency scale (the scene's noise tables), mode rt_noise_mode */
    RT_TEX_IMAGE = 3,   /* image `image`, by (u, v), nearest texel as the book */
} rt_texture_kind;

typedef enum rt_noise_mode {
    RT_NOISE_PLAIN = 0,  /* 0.5 (1 + noise(scale p)) */
    RT_NOISE_TURB = 1,   /* turbulence(scale p), 7 octaves */
    RT_NOISE_MARBLE = 2, /* 0.5 (1 + sin(scale p.z + 10 turbulence(scale p))): book 2's final noise_texture */
} rt_noise_mode;

typedef struct rt_texture {
    uint32_t kind;      /* rt_texture_kind */
    rt_vec3 color;      /* solid; noise: the colour the noise scales (the book's white) */
    double scale;       /* checker: cell size; noise: frequency */
    uint32_t even, odd; /* checker: indices of textures listed before this one */
    uint32_t mode;      /* noise: rt_noise_mode */
    uint32_t image;     /* image: index into images */
} rt_texture;

/* An image's texels: width * height x 3 bytes (8-bit R, G, B as in the
 * file, row-major from the top row) at texels + offset. The book divides
 * them by 255 and uses them as albedo, with no decoding of sRGB. */
typedef struct rt_image {
    uint32_t width, height;
    uint64_t offset;
} rt_image;

/* A constant-density medium (book 2's constant_medium) inside a closed
 * convex boundary: a sphere (shape RT_MEDIUM_SPHERE) or the quads
 * [first, first + count) of hull (RT_MEDIUM_HULL, a box's six). The
 * boundary is not a surface: a visible one (the book's glass ball) is a
 * sphere of its own. material: isotropic. The camera may be inside. */
typedef enum rt_medium_shape {
    RT_MEDIUM_SPHERE = 0,
    RT_MEDIUM_HULL = 1,
} rt_medium_shape;

typedef struct rt_medium {
    uint32_t shape; /* rt_medium_shape */
    rt_vec3 center; /* sphere */
    double radius;  /* sphere */
    uint32_t first, count; /* hull quads */
    double density; /* > 0 */
    uint32_t material;
} rt_medium;

/* A growing list of T: items, n, cap. */
#define RT_LIST(T)                                                                                                    \
    struct {                                                                                                          \
        T *items;                                                                                                     \
        uint32_t n;                                                                                                   \
        size_t cap;                                                                                                   \
    }

/* What the book-2 scenes add; all empty in book 1's. */
/* Index fields that say "0: none, else 1 + index" (texture, frame) keep
 * a zero-initialised record plain. */
typedef struct rt_scene_shapes {
    RT_LIST(rt_quad) quads;
    RT_LIST(rt_mover) movers;
    RT_LIST(rt_frame) frames;
} rt_scene_shapes;

typedef struct rt_scene_media {
    RT_LIST(rt_medium) media;
    RT_LIST(rt_quad) hull; /* the media's boundaries; not surfaces */
} rt_scene_media;

typedef struct rt_scene_textures {
    RT_LIST(rt_texture) textures;
    RT_LIST(rt_image) images;
    uint8_t *texels;
    size_t n_texels, cap_texels; /* bytes */
    uint64_t noise_seed;         /* the Perlin tables' seed (every rank builds them from it) */
} rt_scene_textures;

typedef enum rt_background_kind {
    RT_BACKGROUND_SKY = 0,   /* book 1's gradient sky_bottom .. sky_top by ray direction y */
    RT_BACKGROUND_COLOR = 1, /* one colour (black for lit scenes) */
} rt_background_kind;

typedef struct rt_camera_desc {
    rt_vec3 lookfrom, lookat, vup;
    double vfov_deg;   /* vertical field of view */
    double aperture;   /* lens diameter; 0 = pinhole */
    double focus_dist; /* distance to the plane in focus */
    uint32_t pixels;   /* rt_camera_pixels: how pixel positions map to the viewport */
} rt_camera_desc;

typedef enum rt_camera_pixels {
    RT_PIXELS_SEED = 0,  /* book 1's seeds: u = (x + du) / (W - 1), rows from the bottom */
    RT_PIXELS_BOOK2 = 1, /* books 2-3 (v4): pixel centres a pixel apart, jitter in [-0.5, 0.5) */
} rt_camera_pixels;

/* A camera keyframe (anim.h): the view at time `frame` (a frame number, or
 * any time between two), pixels aside (the scene's camera keeps those). */
typedef struct rt_camera_key {
    double frame;
    rt_vec3 lookfrom, lookat, vup;
    double vfov_deg, aperture, focus_dist;
} rt_camera_key;

typedef struct rt_scene {
    rt_sphere *spheres;
    uint32_t n_spheres;
    size_t cap_spheres;
    rt_material *materials;
    uint32_t n_materials;
    size_t cap_materials;
    rt_camera_desc camera;
    rt_vec3 sky_bottom, sky_top; /* background gradient by ray direction y */
    uint32_t background_kind;    /* rt_background_kind */
    rt_vec3 background;          /* RT_BACKGROUND_COLOR */
    rt_scene_shapes shapes;
    rt_scene_media media;
    rt_scene_textures tex;
    /* Camera keyframes in increasing frame order (anim.h), at most
     * RT_SCENE_MAX_KEYS; none: every frame has `camera`. */
    RT_LIST(rt_camera_key) keys;
} rt_scene;

/* 1: book 1 only, 2: book 2's content (each still written for such
 * scenes), 3: version 2 with camera keyframes. */
#define RT_SCENE_FORMAT_VERSION 3u
/* Camera keyframes, at most: enough for a hand-made path (a key every
 * frame of a 40 s clip at 24 frames/s is 960), small to interpolate. */
#define RT_SCENE_MAX_KEYS 1024u
#define RT_SCENE_MAX_SPHERES 10000000u
/* Media in a scene, at most: the book-2 path loop walks a ray through
 * all of them at every segment. */
#define RT_SCENE_MAX_MEDIA 64u
/* Texels of one image, at most: 2^26 (8192 x 8192, 192 MiB) is 128 times
 * the book's earthmap.jpg (1024 x 512). The image reader refuses a file
 * whose header announces more before decoding it (io/texture_image.h). */
#define RT_SCENE_MAX_IMAGE_PIXELS ((uint64_t)1 << 26)

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

/* ---- book 2's additions (scene_book2.c) ------------------------------------
 * Each takes an rt_xform (xform.h; NULL for none) where a shape can be part
 * of an instance: the shape is stored in world space. RT_EINVAL for a bad
 * argument (a zero-area quad, a material or texture index out of range, a
 * non-finite number, a density <= 0), RT_EOVERFLOW past the format's
 * limits, RT_ENOMEM. */
struct rt_xform;
rt_material rt_scene_emitter(rt_vec3 emit, int two_sided);
rt_material rt_scene_isotropic(rt_vec3 albedo);
/* m with its albedo (emitter: its emission) taken from texture index tex. */
rt_material rt_scene_textured(rt_material m, uint32_t tex);
int rt_scene_add_texture(rt_scene *s, const rt_texture *t, uint32_t *index);
/* Copies width x height RGB texels in. */
int rt_scene_add_image(rt_scene *s, uint32_t width, uint32_t height, const uint8_t *texels, uint32_t *index);
int rt_scene_add_quad(rt_scene *s, rt_vec3 q, rt_vec3 u, rt_vec3 v, uint32_t material, const struct rt_xform *x);
/* The box with opposite corners a and b: six quads facing out. */
int rt_scene_add_box(rt_scene *s, rt_vec3 a, rt_vec3 b, uint32_t material, const struct rt_xform *x);
/* A sphere of an instance: a rotated one keeps its (u, v) through a frame. */
int rt_scene_add_sphere_x(rt_scene *s, rt_vec3 center, double radius, uint32_t material, const struct rt_xform *x);
int rt_scene_add_mover(rt_scene *s, rt_vec3 center0, rt_vec3 center1, double radius, uint32_t material,
                       const struct rt_xform *x);
/* Media of density inside a sphere, or inside the box a..b. */
int rt_scene_add_medium_sphere(rt_scene *s, rt_vec3 center, double radius, double density, uint32_t material);
int rt_scene_add_medium_box(rt_scene *s, rt_vec3 a, rt_vec3 b, double density, uint32_t material,
                            const struct rt_xform *x);
/* Media inside the closed convex hull of n quads (4 to 64), placed by x
 * (a scene file's "hull"; a dump writes every box medium this way). */
int rt_scene_add_medium_hull(rt_scene *s, const rt_quad *quads, uint32_t n, double density, uint32_t material,
                             const struct rt_xform *x);
/* RT_OK when the n quads bound a closed convex body: every edge is an
 * edge of another quad, and every corner lies on one side of each quad's
 * plane (to 1e-9 of the largest coordinate); RT_EINVAL when open (or
 * fewer than 4, more than 64), RT_ERANGE when not convex. */
int rt_scene_hull_check(const rt_quad *quads, uint32_t n);
/* 1 when s uses anything of book 2 (the book-2 path loop renders it). */
int rt_scene_is_book2(const rt_scene *s);

/* The book 1 final scene as seed 000's renderer builds it: ground, a
 * 2grid x 2grid field of small spheres (80/15/5 % lambertian/metal/glass)
 * drawn from the seed's scene stream, and the three large spheres. */
int rt_scene_build_final(rt_scene *s, uint64_t seed, int grid);

/* Serialized form: magic "RTSCENE\0", u32 version, u32 counts, every double
 * as IEEE-754 bits in little endian, then a 64-bit checksum of all that
 * precedes it. serialize -> deserialize -> serialize is byte-identical. */
int rt_scene_serialize(const rt_scene *s, uint8_t **buf, size_t *len);
int rt_scene_deserialize(rt_scene *s, const uint8_t *buf, size_t len);
/* The same for bytes this process's rt_scene_serialize made (rank 0's own
 * broadcast): every check but the checksum's pass over them again, the
 * hash of a textured scene's megabytes (3.5 ms for book2-final's earth). */
int rt_scene_deserialize_own(rt_scene *s, const uint8_t *buf, size_t len);
/* The 64-bit FNV-1a of a whole serialized scene (its checksum included)
 * that rt_scene_deserialize accepted: its checksum, the FNV-1a of all that
 * precedes it, carried on over the checksum's 8 bytes, so no pass over the
 * rest again (a textured scene's megabytes of texels). */
uint64_t rt_scene_bytes_hash(const uint8_t *buf, size_t len);

#endif
