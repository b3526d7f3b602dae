/* texture.h - the colour of a texture at a hit: solid, the book's spatial
 * checker, Perlin noise (plain, turbulence, marble) and images, with book
 * 2's formulas; the noise tables built from the scene's noise seed, the
 * same on every rank. Core layer: no files, no printing. */
#ifndef RT_TEXTURE_H
#define RT_TEXTURE_H

#include <stdint.h>

#include "scene.h"
#include "vec.h"

#define RT_PERLIN_POINTS 256

/* Book 2's Perlin noise: a random unit vector per lattice point through
 * three permutations of 0..255, interpolated with Hermite weights. */
typedef struct rt_perlin {
    rt_vec3 vec[RT_PERLIN_POINTS];
    uint8_t perm[3][RT_PERLIN_POINTS];
} rt_perlin;

/* The tables from seed: only exact arithmetic (and sqrt), so every rank
 * builds the same ones. */
void rt_perlin_init(rt_perlin *p, uint64_t seed);
/* Noise in about [-1, 1] at point x. */
double rt_perlin_noise(const rt_perlin *p, rt_vec3 x);
/* |sum of depth octaves|, each half the weight at twice the frequency. */
double rt_perlin_turb(const rt_perlin *p, rt_vec3 x, int depth);

/* The value of texture `index` of s at (u, v) and hit point p; pn: the
 * scene's noise tables (only read by noise textures). */
rt_vec3 rt_texture_value(const rt_scene *s, const rt_perlin *pn, uint32_t index, double u, double v, rt_vec3 p);

/* A material's colour at a hit: its texture's value (material texture 1 +
 * index), else its albedo (emitters: emit). */
static inline rt_vec3 rt_texture_albedo(const rt_scene *s, const rt_perlin *pn, const rt_material *m, double u,
                                        double v, rt_vec3 p)
{
    if (m->texture)
        return rt_texture_value(s, pn, m->texture - 1, u, v, p);
    return m->kind == RT_MAT_EMITTER ? m->emit : m->albedo;
}

#endif
