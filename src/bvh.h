/* bvh.h - our acceleration structure: a 4-wide bounding volume hierarchy
 * built with the surface area heuristic and traversed four boxes at a time
 * (SSE on x86-64, a scalar loop with the same results elsewhere). */
#ifndef RT_BVH_H
#define RT_BVH_H

#include <stddef.h>
#include <stdint.h>

#include "accel.h"
#include "scene.h"

typedef struct rt_bvh rt_bvh;

int rt_bvh_build(rt_bvh **out, const rt_scene *s);
void rt_bvh_free(rt_bvh *b);
int rt_bvh_closest(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit);
/* The same traversal with the portable box test, a scalar loop: what builds
 * without SSE2 (non-x86 nodes, RT_NO_SIMD) run. It finds the same hits;
 * --accel bvh-scalar renders with it, so any node can check that. */
int rt_bvh_closest_portable(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit);
/* The traversal of rt_bvh_closest, counting as it goes: nodes visited
 * (box tests of four children) and spheres tested, added to *counts. For
 * benchmarks and tests; the two functions above count nothing. */
typedef struct rt_bvh_counts {
    uint64_t nodes, spheres;
} rt_bvh_counts;
int rt_bvh_closest_counted(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit,
                           rt_bvh_counts *counts);
size_t rt_bvh_bytes(const rt_bvh *b);
/* How many spheres the tree leaves out and every query tests first: those
 * whose box is at least as large as the box of all the others (the final
 * scene's ground); at most 4. */
int rt_bvh_outside(const rt_bvh *b);
/* Structure statistics for tests and the summary. */
void rt_bvh_stats(const rt_bvh *b, int *nodes, int *leaves, int *depth);

#endif
