/* world.h - what the book-2 path loop needs of a scene: the closest hit
 * among its quads, moving spheres and static spheres (one BVH of their
 * boxes, or brute force; the spheres' own BVH, accel.h, is book 1's), the
 * spans of a ray inside its media, the hit's surface record with (u, v),
 * and the noise tables. Built with the scene's accelerator (rt_accel_new),
 * for scenes with book-2 content only. */
#ifndef RT_WORLD_H
#define RT_WORLD_H

#include <stdint.h>

#include "material.h"
#include "scene.h"
#include "texture.h"
#include "vec.h"

typedef struct rt_world rt_world;

/* A hit of the book-2 path loop: a static sphere (accel.h's index), a quad
 * or a moving sphere. */
typedef enum rt_shape_kind {
    RT_SHAPE_SPHERE = 0,
    RT_SHAPE_QUAD = 1,
    RT_SHAPE_MOVER = 2,
} rt_shape_kind;

typedef struct rt_whit {
    double t;
    uint32_t kind; /* rt_shape_kind */
    uint32_t index;
    uint32_t material; /* the shape's (rt_world_closest fills it; rt_world_material gives any shape's) */
} rt_whit;

/* How rt_world_closest finds its hit: the wide tree with the fastest box
 * test the CPU has (AVX, else SSE2, else the portable one), or in a room
 * of a few quads on a CPU with AVX-512 every quad at once (world_flat.c);
 * brute force (every shape: the oracle); or the tree with the SSE2 or the
 * portable box test whatever the CPU (what other nodes run; --accel
 * bvh-sse and bvh-scalar). All of them find the same hits. */
typedef enum rt_world_mode {
    RT_WORLD_BVH = 0,
    RT_WORLD_BRUTE = 1,
    RT_WORLD_BVH_SSE = 2,
    RT_WORLD_BVH_SCALAR = 3,
    RT_WORLD_FLAT = 4, /* RT_WORLD_BVH with the flat test whatever the scene's size (tests) */
} rt_world_mode;

/* Levels of the wide tree at most; a deeper tree (degenerate input) is
 * dropped for brute force. */
#define RT_WORLD_DEPTH_MAX 64

/* The world of s for rays whose time is in [t_lo, t_hi] (a sequence's
 * frames: the moving spheres move on, linear in time): their boxes hold
 * them at times 0 and 1 as the book's, and at t_lo and t_hi where those
 * lie outside. */
int rt_world_build(rt_world **out, const rt_scene *s, rt_world_mode mode, double t_lo, double t_hi);
void rt_world_free(rt_world *w);
size_t rt_world_bytes(const rt_world *w);
const rt_perlin *rt_world_perlin(const rt_world *w);
/* 1 when w's tree runs the AVX box test (RT_WORLD_BVH on a CPU with AVX). */
int rt_world_uses_avx(const rt_world *w);
/* The quads w tests all at once instead of walking its tree (world_flat.c:
 * RT_WORLD_BVH in a scene of a few quads on a CPU with AVX-512), or 0. */
uint32_t rt_world_flat_quads(const rt_world *w);
/* The world's quads as rows for tests of many rays at once (path_lanes.c):
 * row k of quad i at rows[k * max + i], rows 0-2 its corner q, 3-5 its
 * unit normal, 6-8 and 9-11 the vectors whose dot products with a point's
 * offset from q are its edge coordinates, 12 its plane's offset (the
 * scalar test's values, world_internal.h's quad_x), and each quad's
 * material in mat[i]. Returns the count when every item is a static quad,
 * at most max of them, and w walks its tree's AVX test or the flat test
 * (RT_WORLD_BVH: the other modes stay the oracles the tests compare
 * with); else 0. */
uint32_t rt_world_quad_rows(const rt_world *w, double *rows, uint32_t *mat, uint32_t max);

/* The closest quad, moving sphere (at the ray's time) or static sphere
 * with tmin < t <= tmax: the least t, of equal ones the quads before the
 * moving spheres before the static spheres, and the lower index (the same
 * answer from the BVH and brute force, in any order). Returns 1 and fills
 * *hit on a hit. */
int rt_world_closest(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax, rt_whit *hit);

/* rt_world_closest's answer for a ray that leaves the surface of hit
 * `from` (the path's last hit, or NULL): when that is a glass sphere the
 * ray starts inside, found without the walk (world_rooms.c). */
int rt_world_closest_from(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax,
                          const rt_whit *from, rt_whit *hit);

/* The glass spheres whose insides rt_world_closest_from answers without the
 * walk (0 in brute-force mode). */
uint32_t rt_world_rooms(const rt_world *w);

/* Candidate lists for the camera rays of a width x height image taken with
 * cam (as rt_camera_init set it up for that image's aspect), its pixels
 * mapped as the scene's camera says (book2_pixels: RT_PIXELS_BOOK2),
 * tiles of 8 x 8 pixels (world_lists.c). Status code. */
typedef struct rt_world_lists rt_world_lists;
struct rt_camera;
int rt_world_lists_build(rt_world_lists **out, const rt_world *w, const struct rt_camera *cam, int book2_pixels,
                         uint32_t width, uint32_t height);
void rt_world_lists_free(rt_world_lists *l);
size_t rt_world_lists_bytes(const rt_world_lists *l);
/* Tiles with a list, and the items in the lists, for the summary. */
void rt_world_lists_stats(const rt_world_lists *l, uint32_t *tiles, uint32_t *listed, size_t *candidates);
/* Pixel (x, y)'s list: its length (-1 when its tile has none) and its
 * start through *first. */
int32_t rt_world_lists_tile(const rt_world_lists *l, uint32_t x, uint32_t y, uint32_t *first);
/* rt_world_closest's answer for a camera ray of a pixel whose list is
 * (first, n >= 0), from the list alone. */
int rt_world_closest_listed(const rt_world *w, const rt_world_lists *l, uint32_t first, int32_t n, const rt_ray *ray,
                            double time, double tmin, double tmax, rt_whit *hit);

/* Whether a shape stands in front of shape (kind, index) whose hit is at
 * tmax: 1 when one has tmin < t < tmax, or t == tmax and it would win the
 * tie in rt_world_closest's rule. Stops at the first it finds: shadow
 * rays. */
int rt_world_occluded(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax, uint32_t kind,
                      uint32_t index);

/* The t > tmin at which ray (at time `time`) hits shape (kind, index),
 * with the bits rt_world_closest finds; 0 when it misses it. */
int rt_world_shape_t(const rt_world *w, uint32_t kind, uint32_t index, const rt_ray *ray, double time, double tmin,
                     double *t);

/* The span [*t0, *t1] of the whole line orig + t dir inside medium k's
 * boundary (t may be negative); 0 when the line misses it. */
int rt_world_medium_span(const rt_world *w, uint32_t k, const rt_ray *ray, double *t0, double *t1);

/* rt_world_medium_span of a sphere medium m, inline for the path loop's
 * media (path2.c's flights): no call, so nothing of its caller spills. */
static inline int rt_world_sphere_span(const rt_medium *m, const rt_ray *ray, double *t0, double *t1)
{
    const rt_vec3 oc = rt_v3_sub(ray->orig, m->center);
    const double a = rt_v3_len2(ray->dir), hb = rt_v3_dot(oc, ray->dir);
    const double c = rt_v3_dot(oc, oc) - m->radius * m->radius, disc = hb * hb - a * c;
    if (!(disc > 0))
        return 0;
    const double sq = sqrt(disc);
    *t0 = (-hb - sq) / a;
    *t1 = (-hb + sq) / a;
    return 1;
}

/* The surface record of hit h of ray (time: its time), with (u, v) when
 * want_uv (a textured material): spheres by the book's longitude and
 * latitude of the object-space normal, quads by their edge coordinates. */
void rt_world_surface(const rt_world *w, const rt_whit *h, const rt_ray *ray, double time, int want_uv,
                      rt_surface *rec, double *u, double *v);

/* The material of hit h's shape (kind, index; h->material not read). */
uint32_t rt_world_material(const rt_world *w, const rt_whit *h);

#endif
