/* job.h - what a render is: everything that decides a pixel's value. The
 * one description of the job: the options fill it, the renderer, the
 * schedule and the checkpoint read it, the summary prints it. How the work
 * is spread (ranks, threads, bands) is not part of it. */
#ifndef RT_JOB_H
#define RT_JOB_H

#include <stdint.h>

#include "material.h"
#include "sampler.h"

/* rt_job.light: how the book-2 path loop finds the emitters of a scene
 * that has some (lights.h). */
typedef enum rt_light_mode {
    RT_LIGHT_MIS = 0,      /* next-event estimation and BSDF sampling, by MIS (nee.h) */
    RT_LIGHT_BRUTE = 1,    /* --no-light-sampling: only paths that hit an emitter by chance */
    RT_LIGHT_NEE_ONLY = 2, /* next-event estimation alone after diffuse vertices (tests) */
} rt_light_mode;

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
    /* Adaptive sampling: 0 = off, else the relative error a pixel's count
     * of samples is chosen for (render.h: RT_ADAPT_*). */
    double noise_threshold;
    uint32_t aov; /* RT_AOV_* bits: the buffers a denoiser wants */
    uint32_t light; /* rt_light_mode */
} rt_job;

/* Extra buffers per pixel, averaged over its samples like its colour: the
 * albedo and the shading normal of the first non-specular hit. */
#define RT_AOV_ALBEDO 1u
#define RT_AOV_NORMAL 2u

/* The values a pixel's sums hold, at these offsets (0 = absent; the colour
 * is always at 0..2): with adaptive sampling, the samples it took, then
 * the albedo and the normal when asked for. ch values per pixel in all.
 * The render core, the farm, the checkpoint and the image writers lay out
 * a block of rows as row-major pixels of ch values each. */
typedef struct rt_layout {
    uint32_t ch, count, albedo, normal;
} rt_layout;

static inline rt_layout rt_job_layout(const rt_job *j)
{
    rt_layout l = {.ch = 3};
    if (j->noise_threshold > 0.0)
        l.count = l.ch++;
    if (j->aov & RT_AOV_ALBEDO)
        l.albedo = l.ch, l.ch += 3;
    if (j->aov & RT_AOV_NORMAL)
        l.normal = l.ch, l.ch += 3;
    return l;
}

#endif
