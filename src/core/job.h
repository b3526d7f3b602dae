/* job.h - what a render is: everything that decides a pixel's value. The
 * one description of the job: the options fill it, the renderer, the
 * schedule and the checkpoint read it, the summary prints it. How the work
 * is spread (ranks, threads, bands) is not part of it. */
#ifndef RT_JOB_H
#define RT_JOB_H

#include <stdint.h>

#include "material.h"

typedef struct rt_job {
    uint32_t width, height;
    uint32_t samples;   /* samples per pixel of the whole job */
    uint32_t max_depth; /* maximum ray segments per path */
    uint64_t seed;      /* scene and sampling seed */
    rt_diffuse diffuse;
} rt_job;

#endif
