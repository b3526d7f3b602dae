/* accel.h - closest-hit queries against the scene's spheres. One interface,
 * several intersectors: our BVH (default), brute force (the seeds'
 * algorithm, kept as the correctness oracle) and, in builds configured with
 * -DRT_EMBREE=ON, Embree 3 for side-by-side benchmarks. */
#ifndef RT_ACCEL_H
#define RT_ACCEL_H

#include <stdint.h>

#include "scene.h"
#include "vec.h"

typedef enum rt_accel_kind {
    RT_ACCEL_BVH = 0,
    RT_ACCEL_BRUTE = 1,
    RT_ACCEL_EMBREE = 2,
    RT_ACCEL_BVH_SCALAR = 3, /* our BVH with the portable box test (as non-x86 nodes run it) */
    RT_ACCEL_BVH_SSE = 4,    /* our BVH with the SSE2 box test even on AVX CPUs (as x86-64 CPUs without AVX run it) */
} rt_accel_kind;

typedef struct rt_hit {
    double t;      /* distance along the ray (in units of |dir|) */
    uint32_t prim; /* index into scene->spheres */
} rt_hit;

typedef struct rt_accel rt_accel;

/* Builds the structure for scene s (which must outlive it). Returns
 * RT_EUNSUPPORTED for RT_ACCEL_EMBREE in builds without Embree. */
int rt_accel_new(rt_accel **out, const rt_scene *s, rt_accel_kind kind);
/* The same for rays whose time is in [t_lo, t_hi] (the frames of a job,
 * rt_anim_frame's intervals; rt_accel_new: the book's [0, 1]). */
int rt_accel_new_span(rt_accel **out, const rt_scene *s, rt_accel_kind kind, double t_lo, double t_hi);
void rt_accel_free(rt_accel *a);

/* Closest sphere hit with tmin < t <= tmax (rt_sphere_closer's rule: the
 * least t, of equal ones the lowest sphere index); returns 1 on a hit. Safe
 * to call from many threads at once. */
int rt_accel_closest(const rt_accel *a, const rt_ray *ray, double tmin, double tmax, rt_hit *hit);

/* "bvh", "brute", "embree", "bvh-scalar", "bvh-sse"; and parsing back (-1
 * when unknown). */
const char *rt_accel_name(rt_accel_kind kind);
int rt_accel_parse(const char *name);
/* The box test our BVH (or, for a book-2 scene, the world's tree) runs in
 * a ("avx", "sse2" or "portable"), NULL for the other intersectors and
 * for the world's flat test. */
const char *rt_accel_box_test(const rt_accel *a);
/* The quads a's world tests all at once instead of walking its tree
 * (world.h, rt_world_flat_quads), or 0. */
uint32_t rt_accel_flat_quads(const rt_accel *a);
/* Our BVH inside a when a runs it with the AVX box test (the bvh kind on a
 * CPU with AVX), else NULL: for code compiled for AVX that calls
 * rt_bvh_closest_avx itself (path.h's path loop). */
const struct rt_bvh *rt_accel_bvh_avx(const rt_accel *a);
/* The scene's quads, moving spheres, media and noise tables (world.h) when
 * it has book-2 content (rt_scene_is_book2), else NULL. */
const struct rt_world *rt_accel_world(const rt_accel *a);
/* The scene's emitters as lights (lights.h) when it has book-2 content and
 * emitters, else NULL. */
const struct rt_lights *rt_accel_lights(const rt_accel *a);
/* Bytes the structure occupies (for the memory report). */
size_t rt_accel_bytes(const rt_accel *a);
/* Our BVH inside a (the bvh, bvh-scalar and bvh-sse kinds, for scenes
 * without book-2 content: the world's tree holds a book-2 scene's spheres),
 * else NULL: for tests and benchmarks that query it directly
 * (rt_bvh_closest_counted). */
const struct rt_bvh *rt_accel_bvh(const rt_accel *a);

#endif
