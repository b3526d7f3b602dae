/* bvh.h - our acceleration structure: an 8-wide bounding volume hierarchy
 * built with the surface area heuristic, whose traversal tests a node's
 * eight boxes at once with AVX where the CPU has it, four at a time with SSE2
 * on other x86-64 CPUs, and in a scalar loop elsewhere, all with the same
 * results. */
#ifndef RT_BVH_H
#define RT_BVH_H

#include <stddef.h>
#include <stdint.h>

#include "accel.h"
#include "scene.h"

typedef struct rt_bvh rt_bvh;

int rt_bvh_build(rt_bvh **out, const rt_scene *s);
void rt_bvh_free(rt_bvh *b);
/* The box tests a build has: SSE2 on x86-64 (unless RT_NO_SIMD); AVX too,
 * picked at run time, in x86-64 builds with GCC or clang. */
#if defined(__SSE2__) && !defined(RT_NO_SIMD)
#define RT_BVH_HAVE_SSE2 1
#else
#define RT_BVH_HAVE_SSE2 0
#endif
#if RT_BVH_HAVE_SSE2 && defined(__x86_64__) && defined(__GNUC__) && !defined(RT_NO_AVX)
#define RT_BVH_HAVE_AVX 1
#else
#define RT_BVH_HAVE_AVX 0
#endif

/* Closest hit with the fastest box test the CPU has (rt_bvh_uses_avx). */
int rt_bvh_closest(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit);
/* The same traversal with the baseline box test: SSE2 on x86-64 even where
 * AVX is present (what x86-64 CPUs without AVX run), else the portable one.
 * It finds the same hits; --accel bvh-sse renders with it. */
int rt_bvh_closest_sse(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit);
/* The same traversal with the portable box test, a scalar loop: what builds
 * without SSE2 (non-x86 nodes, RT_NO_SIMD) run. It finds the same hits;
 * --accel bvh-scalar renders with it, so any node can check that. */
int rt_bvh_closest_portable(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit);
/* 1 when rt_bvh_closest runs the AVX box test (the CPU has AVX), else 0. */
int rt_bvh_uses_avx(const rt_bvh *b);
#if RT_BVH_HAVE_AVX
/* The AVX traversal on its own, for code compiled for AVX to inline
 * (render.c's path loop); only when rt_bvh_uses_avx. */
__attribute__((target("avx"))) int rt_bvh_closest_avx(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax,
                                                      rt_hit *hit);
/* rt_bvh_closest_packet's AVX traversal, for code compiled for AVX
 * (render.c's path loop: camera rays and full groups); only when rt_bvh_uses_avx. */
__attribute__((target("avx"))) int rt_bvh_closest_packet_avx(const rt_bvh *b, const rt_ray *rays, int n,
                                                             double tmin, double tmax, rt_hit *hits);
#endif
size_t rt_bvh_bytes(const rt_bvh *b);

#endif
