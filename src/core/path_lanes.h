/* path_lanes.h - the book-2 path loop eight paths at a time in AVX-512
 * lanes (path_lanes.c), for scenes of a few quads, lit by their sampled
 * lights or by brute force;
 * the same image as path2.c's loop. Core-internal: team.c's runs of
 * pixels call it where the renderer says so (rt_renderer.lanes). */
#ifndef RT_PATH_LANES_H
#define RT_PATH_LANES_H

#include <stdint.h>

#include "render.h"

/* A run's pixels at most, and the paths a run is made long enough for. */
#define RT_PATH_LANES_RUN_PIXELS 16
#define RT_PATH_LANES_RUN_PATHS 128

/* 1 when r's job and scene can run in the lanes on this CPU: AVX-512 F and
 * DQ; a world of static quads only (at most 32), lambertian (no texture)
 * or emitting (no texture); no media; lights sampled or not; the lambertian
 * diffuse model; the Sobol sampler; no buffers beyond the colour (no AOV,
 * no adaptive sampling); the world's default walk (rt_world_quad_rows). */
int rt_path_lanes_for(const rt_renderer *r);
/* The pixels of a run for pixels of `samples` samples each (at most
 * RT_PATH_LANES_RUN_PIXELS). */
uint32_t rt_path_lanes_run_pixels(uint32_t samples);
/* Pixels [i0, i1) of a block of columns [x0, x0 + w) and rows from y0 (as
 * dispatch.h's rt_dispatch_block_pixel), samples [s0, s1) of each, added to
 * acc; returns the ray segments traced. Only where rt_path_lanes_for. */
uint64_t rt_path_lanes_run(const rt_renderer *r, uint32_t x0, uint32_t w, uint32_t y0, uint32_t s0, uint32_t s1,
                           long i0, long i1, int64_t *acc);

/* Tests: the lanes' closest quad of eight rays from w's quads (the scene
 * s gives their materials), t and the quad in id (-1: none) as the path
 * loop finds them; returns the quads tested (0: w is not for the lanes). */
struct rt_world;
uint32_t rt_path_lanes_closest(const struct rt_world *w, const rt_scene *s, const rt_ray ray[8], double t[8],
                               int64_t id[8]);

#endif
