/* texture.c - texture values and Perlin noise (book 2, chapters 4-5). */
#include "texture.h"
#include "core_internal.h"

#include <math.h>

#include "detmath.h"
#include "rng.h"


void rt_perlin_init(rt_perlin *p, uint64_t seed)
{
    rt_rng r = rt_rng_for_stream(seed, RT_STREAM_PERLIN);
    for (int i = 0; i < RT_PERLIN_POINTS; i++) {
        rt_vec3 v;
        do { /* a direction: uniform in the cube, not too close to 0; z, y, x drawn in turn (the order
              * GCC's builds drew them in when the three were arguments of one call, whose order C
              * leaves open: clang's drew x first, other tables, other images) */
            v.z = rt_rng_range(&r, -1, 1);
            v.y = rt_rng_range(&r, -1, 1);
            v.x = rt_rng_range(&r, -1, 1);
        } while (!(rt_v3_len2(v) > 1e-6));
        p->vec[i] = rt_v3_unit(v);
    }
    for (int a = 0; a < 3; a++) { /* Fisher-Yates, integer only */
        for (int i = 0; i < RT_PERLIN_POINTS; i++)
            p->perm[a][i] = (uint8_t)i;
        for (int i = RT_PERLIN_POINTS - 1; i > 0; i--) {
            const int j = (int)(rt_rng_next(&r) % (uint64_t)(i + 1));
            const uint8_t t = p->perm[a][i];
            p->perm[a][i] = p->perm[a][j];
            p->perm[a][j] = t;
        }
    }
}

/* floor(x) as an int, for the lattice; huge or non-finite x: 0. */
static int lattice(double x, double *frac)
{
    if (!(x > -2e9 && x < 2e9)) {
        *frac = 0.0;
        return 0;
    }
    const double f = floor(x);
    *frac = x - f;
    return (int)f;
}

double rt_perlin_noise(const rt_perlin *p, rt_vec3 x)
{
    double fu, fv, fw;
    const int i = lattice(x.x, &fu), j = lattice(x.y, &fv), k = lattice(x.z, &fw);
    const double uu = fu * fu * (3 - 2 * fu), vv = fv * fv * (3 - 2 * fv), ww = fw * fw * (3 - 2 * fw);
    double sum = 0.0;
    for (int di = 0; di < 2; di++)
        for (int dj = 0; dj < 2; dj++)
            for (int dk = 0; dk < 2; dk++) {
                const rt_vec3 g = p->vec[p->perm[0][(i + di) & 255] ^ p->perm[1][(j + dj) & 255] ^
                                         p->perm[2][(k + dk) & 255]];
                const rt_vec3 w = rt_v3(fu - di, fv - dj, fw - dk);
                sum += (di * uu + (1 - di) * (1 - uu)) * (dj * vv + (1 - dj) * (1 - vv)) *
                       (dk * ww + (1 - dk) * (1 - ww)) * rt_v3_dot(g, w);
            }
    return sum;
}

double rt_perlin_turb(const rt_perlin *p, rt_vec3 x, int depth)
{
    double sum = 0.0, weight = 1.0;
    for (int d = 0; d < depth; d++) {
        sum += weight * rt_perlin_noise(p, x);
        weight *= 0.5;
        x = rt_v3_scale(x, 2.0);
    }
    return fabs(sum);
}

/* Cell parity of the checker: floor(p / cell) summed over the axes. */
static int checker_odd(double inv, rt_vec3 p)
{
    double f;
    const long sum = (long)lattice(inv * p.x, &f) + lattice(inv * p.y, &f) + lattice(inv * p.z, &f);
    return (int)(sum & 1);
}

static rt_vec3 image_value(const rt_scene *s, const rt_image *im, double u, double v)
{
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    v = 1.0 - (v < 0 ? 0 : v > 1 ? 1 : v); /* image rows from the top */
    uint32_t i = (uint32_t)(u * im->width), j = (uint32_t)(v * im->height);
    i = i < im->width ? i : im->width - 1;
    j = j < im->height ? j : im->height - 1;
    const uint8_t *t = s->tex.texels + im->offset + ((size_t)j * im->width + i) * 3;
    const double k = 1.0 / 255.0;
    return rt_v3(t[0] * k, t[1] * k, t[2] * k);
}

rt_vec3 rt_texture_value(const rt_scene *s, const rt_perlin *pn, uint32_t index, double u, double v, rt_vec3 p)
{
    const rt_texture *t = &s->tex.textures.items[index];
    while (t->kind == RT_TEX_CHECKER) /* its cells are listed before it: this ends */
        t = &s->tex.textures.items[checker_odd(1.0 / t->scale, p) ? t->odd : t->even];
    switch (t->kind) {
    case RT_TEX_NOISE: {
        const rt_vec3 x = rt_v3_scale(p, t->scale);
        double n;
        if (t->mode == RT_NOISE_PLAIN)
            n = 0.5 * (1.0 + rt_perlin_noise(pn, x));
        else if (t->mode == RT_NOISE_TURB)
            n = rt_perlin_turb(pn, x, 7);
        else
            n = 0.5 * (1.0 + rt_det_sin(x.z + 10.0 * rt_perlin_turb(pn, x, 7)));
        return rt_v3_scale(t->color, n);
    }
    case RT_TEX_IMAGE:
        return image_value(s, &s->tex.images.items[t->image], u, v);
    default:
        return t->color;
    }
}
