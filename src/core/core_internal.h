/* core_internal.h - the core's entry points that only its tests and the
 * benchmarks (tools/bench) call: no other layer includes this header. They
 * stay exported so a test can check a piece on its own (one sample, one
 * traversal, one Fresnel term) against an oracle. */
#ifndef RT_CORE_INTERNAL_H
#define RT_CORE_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "bvh.h"
#include "camera.h"
#include "material.h"
#include "render.h"
#include "scene.h"

/* ---- render.c ---- */
/* Colour of one sample of pixel (x, y), y counted from the top row. Adds the
 * number of ray segments traced to *segments. */
rt_vec3 rt_render_sample(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t sample, uint64_t *segments);

/* The rays that sample traces, in order (rays holds max_depth entries);
 * returns how many. For timing intersectors on the renderer's own rays. */
uint32_t rt_render_sample_rays(const rt_renderer *r, uint32_t x, uint32_t y, uint32_t sample, rt_ray *rays);

/* Adds samples [s0, s1) of rows [y0, y1) to acc, laid out as
 * acc[((y - y0) * width + x) * ch + value] (ch and the values: r->lay), using nthreads OpenMP threads
 * (0 = the OpenMP default). Returns the ray segments traced. One block
 * with a barrier at its end: the farm renders its units with
 * rt_render_stream instead; the tests compare it with this. */
uint64_t rt_render_rows(const rt_renderer *r, uint32_t y0, uint32_t y1, uint32_t s0, uint32_t s1, int64_t *acc,
                        int nthreads);

/* ---- scene.c ---- */
/* FNV-1a 64 of the serialized bytes: identifies the scene in logs and
 * checkpoints. */
uint64_t rt_scene_hash(const rt_scene *s);

/* ---- camera.c ---- */
/* The same ray for the lens sample (lx, ly) of the unit disk. */
rt_ray rt_camera_ray_lens(const rt_camera *cam, double s, double t, double lx, double ly);

/* ---- material.c ---- */
/* Schlick's approximation of Fresnel reflectance. */
double rt_material_reflectance(double cosine, double ref_idx);

/* ---- bvh.c, bvh_build.c ---- */
/* The closest hits of n rays (1 <= n <= 8), into hits[k] for the rays whose bit is
 * set in the returned mask: the same hits as rt_bvh_closest finds for each,
 * from one traversal of them all together where the CPU has AVX
 * (rt_bvh_closest_packet_avx), else one at a time. */
int rt_bvh_closest_packet(const rt_bvh *b, const rt_ray *rays, int n, double tmin, double tmax, rt_hit *hits);
/* The traversal of rt_bvh_closest, counting as it goes: nodes visited
 * (box tests of up to eight children) and spheres tested, added to *counts. For
 * benchmarks and tests; the two functions above count nothing. */
typedef struct rt_bvh_counts {
    uint64_t nodes, spheres;
} rt_bvh_counts;
int rt_bvh_closest_counted(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit,
                           rt_bvh_counts *counts);
/* How many spheres the tree leaves out and every query tests first: those
 * whose box is at least as large as the box of all the others (the final
 * scene's ground); at most 4. */
int rt_bvh_outside(const rt_bvh *b);
/* Structure statistics for tests and the summary. */
void rt_bvh_stats(const rt_bvh *b, int *nodes, int *leaves, int *depth);

#endif
