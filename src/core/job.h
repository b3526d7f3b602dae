/* job.h - what a render is: everything that decides a pixel's value. The
 * one description of the job: the options fill it, the renderer, the
 * schedule and the checkpoint read it, the summary prints it. How the work
 * is spread (ranks, threads, bands) is not part of it. */
#ifndef RT_JOB_H
#define RT_JOB_H

#include <stdint.h>

#include "material.h"
#include "sampler.h"

typedef struct rt_job {
    uint32_t width, height;
    uint32_t samples;   /* samples per pixel of the whole job */
    uint32_t max_depth; /* maximum ray segments per path */
    uint64_t seed;      /* scene and sampling seed */
    rt_diffuse diffuse;
    rt_sampler_kind sampler; /* RT_SAMPLER_RANDOM (0) draws sampling version 2's numbers */
    int roulette;            /* Russian roulette after roulette_depth bounces */
    /* Bounces before the roulette; 0 means RT_RENDER_ROULETTE_DEPTH (tests
     * start it at the first bounce, where a furnace shows its weight). */
    uint32_t roulette_depth;
} rt_job;

#endif
