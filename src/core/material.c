/* material.c - lambertian (three diffuse models), metal and dielectric. */
#include "material.h"
#include "core_internal.h"

#include <math.h>
#include <string.h>

#include "sampler.h"

static const char *const DIFFUSE_NAMES[] = {"lambertian", "sphere", "hemisphere"}; /* rt_diffuse order */

const char *rt_diffuse_name(rt_diffuse model)
{
    return (unsigned)model < 3 ? DIFFUSE_NAMES[model] : "?";
}

int rt_diffuse_parse(const char *name)
{
    for (int k = 0; k < 3; k++)
        if (!strcmp(name, DIFFUSE_NAMES[k]))
            return k;
    return -1;
}

void rt_surface_from_sphere(rt_surface *rec, const rt_sphere *sp, const rt_ray *ray, double t)
{
    rec->t = t;
    rec->p = rt_ray_at(ray, t);
    /* Dividing by the signed radius flips the normal of a hollow sphere. */
    rt_vec3 outward = rt_v3_scale(rt_v3_sub(rec->p, sp->center), 1.0 / sp->radius);
    rec->front_face = rt_v3_dot(ray->dir, outward) < 0.0;
    rec->normal = rec->front_face ? outward : rt_v3_neg(outward);
}

double rt_material_reflectance(double cosine, double ref_idx)
{
    double r0 = (1.0 - ref_idx) / (1.0 + ref_idx);
    r0 = r0 * r0;
    double x = 1.0 - cosine, x2 = x * x;
    return r0 + (1.0 - r0) * (x2 * x2 * x); /* pow(x, 5) without libm */
}

static rt_vec3 refract(rt_vec3 uv, rt_vec3 n, double etai_over_etat, double cos_theta)
{
    rt_vec3 perp = rt_v3_scale(rt_v3_add(uv, rt_v3_scale(n, cos_theta)), etai_over_etat);
    rt_vec3 para = rt_v3_scale(n, -sqrt(fabs(1.0 - rt_v3_len2(perp))));
    return rt_v3_add(perp, para);
}

int rt_material_scatter(const rt_material *m, const rt_ray *in, const rt_surface *rec, rt_diffuse model,
                        rt_sampler *smp, rt_vec3 *attenuation, rt_ray *scattered)
{
    scattered->orig = rec->p;
    switch (m->kind) {
    case RT_MAT_LAMBERTIAN: {
        rt_vec3 dir;
        if (model == RT_DIFFUSE_HEMISPHERE)
            dir = rt_sampler_hemisphere(smp, rec->normal);
        else if (model == RT_DIFFUSE_SPHERE)
            dir = rt_v3_add(rec->normal, rt_sampler_ball(smp));
        else
            dir = rt_warp_cosine(rt_sampler_get2d(smp), rec->normal);
        if (rt_v3_near_zero(dir))
            dir = rec->normal;
        scattered->dir = dir;
        *attenuation = m->albedo;
        return 1;
    }
    case RT_MAT_METAL: {
        rt_vec3 reflected = rt_v3_reflect(rt_v3_unit(in->dir), rec->normal);
        if (m->fuzz > 0.0)
            reflected = rt_v3_add(reflected, rt_v3_scale(rt_sampler_ball(smp), m->fuzz));
        scattered->dir = reflected;
        *attenuation = m->albedo;
        return rt_v3_dot(reflected, rec->normal) > 0.0;
    }
    case RT_MAT_DIELECTRIC: {
        double ratio = rec->front_face ? 1.0 / m->ior : m->ior;
        rt_vec3 ud = rt_v3_unit(in->dir);
        double cos_theta = fmin(-rt_v3_dot(ud, rec->normal), 1.0);
        double sin_theta = sqrt(1.0 - cos_theta * cos_theta);
        int cannot_refract = ratio * sin_theta > 1.0;
        if (cannot_refract || rt_material_reflectance(cos_theta, ratio) > rt_sampler_get1d(smp))
            scattered->dir = rt_v3_reflect(ud, rec->normal);
        else
            scattered->dir = refract(ud, rec->normal, ratio, cos_theta);
        *attenuation = rt_v3(1.0, 1.0, 1.0);
        return 1;
    }
    }
    return 0;
}
