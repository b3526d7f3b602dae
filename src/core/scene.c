/* scene.c - scene construction, the book's final scene, and the byte format. */
#include "scene.h"
#include "core_internal.h"

#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "hash.h"
#include "rng.h"
#include "status.h"

void rt_scene_init(rt_scene *s)
{
    memset(s, 0, sizeof *s);
    s->sky_bottom = rt_v3(1.0, 1.0, 1.0);
    s->sky_top = rt_v3(0.5, 0.7, 1.0);
    s->camera.vup = rt_v3(0, 1, 0);
    s->camera.vfov_deg = 90.0;
    s->camera.focus_dist = 1.0;
    s->camera.lookat = rt_v3(0, 0, -1);
}

void rt_scene_free(rt_scene *s)
{
    free(s->spheres);
    free(s->materials);
    free(s->shapes.quads.items);
    free(s->shapes.movers.items);
    free(s->shapes.frames.items);
    free(s->media.media.items);
    free(s->media.hull.items);
    free(s->tex.textures.items);
    free(s->tex.images.items);
    free(s->tex.texels);
    memset(s, 0, sizeof *s);
}

/* Room for one more element, within the scene format's limit. */
static int grow(void **p, size_t *cap, uint32_t n, size_t elem)
{
    return n >= RT_SCENE_MAX_SPHERES ? RT_EOVERFLOW : rt_array_reserve(p, cap, (size_t)n + 1, elem);
}

int rt_scene_add_material(rt_scene *s, const rt_material *m, uint32_t *index)
{
    int st = grow((void **)&s->materials, &s->cap_materials, s->n_materials, sizeof *m);
    if (st)
        return st;
    s->materials[s->n_materials] = *m;
    if (index)
        *index = s->n_materials;
    s->n_materials++;
    return RT_OK;
}

int rt_scene_add_sphere(rt_scene *s, rt_vec3 center, double radius, uint32_t material)
{
    if (material >= s->n_materials || !(radius != 0.0) || !isfinite(radius))
        return RT_EINVAL;
    int st = grow((void **)&s->spheres, &s->cap_spheres, s->n_spheres, sizeof *s->spheres);
    if (st)
        return st;
    rt_sphere *sp = &s->spheres[s->n_spheres++];
    sp->center = center;
    sp->radius = radius;
    sp->material = material;
    sp->frame = 0;
    return RT_OK;
}

int rt_scene_add(rt_scene *s, rt_vec3 c, double r, rt_material m)
{
    uint32_t idx;
    int st = rt_scene_add_material(s, &m, &idx);
    return st ? st : rt_scene_add_sphere(s, c, r, idx);
}

rt_material rt_scene_lambertian(rt_vec3 albedo)
{
    rt_material m = {.kind = RT_MAT_LAMBERTIAN, .albedo = albedo, .fuzz = 0.0, .ior = 1.0};
    return m;
}
rt_material rt_scene_metal(rt_vec3 albedo, double fuzz)
{
    rt_material m = {.kind = RT_MAT_METAL, .albedo = albedo, .fuzz = fuzz < 1.0 ? fuzz : 1.0, .ior = 1.0};
    return m;
}
rt_material rt_scene_dielectric(double ior)
{
    rt_material m = {.kind = RT_MAT_DIELECTRIC, .albedo = rt_v3(1, 1, 1), .fuzz = 0.0, .ior = ior};
    return m;
}

int rt_scene_build_final(rt_scene *s, uint64_t seed, int grid)
{
    if (grid < 0 || grid > 1000)
        return RT_EINVAL;
    rt_scene_init(s);
    rt_rng rng = rt_rng_for_stream(seed, RT_STREAM_SCENE);
    int st = rt_scene_add(s, rt_v3(0, -1000, 0), 1000, rt_scene_lambertian(rt_v3(0.5, 0.5, 0.5)));
    const rt_vec3 focal[3] = {{4, 0.2, 0}, {0, 1, 0}, {-4, 0.2, 0}};
    for (int a = -grid; a < grid && !st; a++) {
        for (int b = -grid; b < grid && !st; b++) {
            /* Draw order follows the seed renderer: material choice, then x, z. */
            double choose = rt_rng_double(&rng);
            double cx = a + 0.9 * rt_rng_double(&rng);
            double cz = b + 0.9 * rt_rng_double(&rng);
            rt_vec3 c = rt_v3(cx, 0.2, cz);
            if (rt_v3_len(rt_v3_sub(c, focal[0])) <= 0.9 || rt_v3_len(rt_v3_sub(c, focal[1])) <= 0.9 ||
                rt_v3_len(rt_v3_sub(c, focal[2])) <= 0.9)
                continue;
            if (choose < 0.8) {
                double r = rt_rng_double(&rng) * rt_rng_double(&rng);
                double g = rt_rng_double(&rng) * rt_rng_double(&rng);
                double bl = rt_rng_double(&rng) * rt_rng_double(&rng);
                st = rt_scene_add(s, c, 0.2, rt_scene_lambertian(rt_v3(r, g, bl)));
            } else if (choose < 0.95) {
                double r = rt_rng_range(&rng, 0.5, 1.0);
                double g = rt_rng_range(&rng, 0.5, 1.0);
                double bl = rt_rng_range(&rng, 0.5, 1.0);
                double fuzz = rt_rng_range(&rng, 0.0, 0.5);
                st = rt_scene_add(s, c, 0.2, rt_scene_metal(rt_v3(r, g, bl), fuzz));
            } else {
                st = rt_scene_add(s, c, 0.2, rt_scene_dielectric(1.5));
            }
        }
    }
    if (!st)
        st = rt_scene_add(s, rt_v3(-4, 1, 0), 1.0, rt_scene_lambertian(rt_v3(0.4, 0.2, 0.1)));
    if (!st)
        st = rt_scene_add(s, rt_v3(0, 1, 0), 1.0, rt_scene_dielectric(1.5));
    if (!st)
        st = rt_scene_add(s, rt_v3(4, 1, 0), 1.0, rt_scene_metal(rt_v3(0.7, 0.6, 0.5), 0.0));
    s->camera.lookfrom = rt_v3(13, 2, 3);
    s->camera.lookat = rt_v3(0, 0, 0);
    s->camera.vup = rt_v3(0, 1, 0);
    s->camera.vfov_deg = 20.0;
    s->camera.aperture = 0.1;
    s->camera.focus_dist = 10.0;
    if (st)
        rt_scene_free(s);
    return st;
}

/* ---- byte format ---------------------------------------------------- */

static const uint8_t MAGIC[8] = {'R', 'T', 'S', 'C', 'E', 'N', 'E', 0};

typedef struct writer {
    uint8_t *p;
} writer;

static void put_u32(writer *w, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        *w->p++ = (uint8_t)(v >> (8 * i));
}
static void put_u64(writer *w, uint64_t v)
{
    for (int i = 0; i < 8; i++)
        *w->p++ = (uint8_t)(v >> (8 * i));
}
static void put_f64(writer *w, double d)
{
    uint64_t v;
    memcpy(&v, &d, 8);
    put_u64(w, v);
}
static void put_v3(writer *w, rt_vec3 v)
{
    put_f64(w, v.x);
    put_f64(w, v.y);
    put_f64(w, v.z);
}

typedef struct reader {
    const uint8_t *p, *end;
    int bad;
} reader;

static uint64_t get_bytes(reader *r, int n)
{
    if (r->end - r->p < n) {
        r->bad = 1;
        r->p = r->end;
        return 0;
    }
    uint64_t v = 0;
    for (int i = 0; i < n; i++)
        v |= (uint64_t)r->p[i] << (8 * i);
    r->p += n;
    return v;
}
static uint32_t get_u32(reader *r) { return (uint32_t)get_bytes(r, 4); }
static double get_f64(reader *r)
{
    uint64_t v = get_bytes(r, 8);
    double d;
    memcpy(&d, &v, 8);
    return d;
}
static rt_vec3 get_v3(reader *r)
{
    double x = get_f64(r), y = get_f64(r), z = get_f64(r);
    return rt_v3(x, y, z);
}

#define MAT_BYTES (4 + 24 + 8 + 8)
#define SPHERE_BYTES (24 + 8 + 4)
#define HEADER_BYTES (8 + 4 + 4 + 4)
#define FIXED_BYTES (4 * 24 + 3 * 8 + 2 * 24)

int rt_scene_serialize(const rt_scene *s, uint8_t **buf, size_t *len)
{
    size_t n = HEADER_BYTES + FIXED_BYTES + (size_t)s->n_materials * MAT_BYTES +
               (size_t)s->n_spheres * SPHERE_BYTES + 8;
    uint8_t *b = malloc(n);
    if (!b)
        return RT_ENOMEM;
    writer w = {b};
    memcpy(w.p, MAGIC, 8);
    w.p += 8;
    put_u32(&w, RT_SCENE_FORMAT_VERSION);
    put_u32(&w, s->n_materials);
    put_u32(&w, s->n_spheres);
    const rt_camera_desc *c = &s->camera;
    put_v3(&w, c->lookfrom);
    put_v3(&w, c->lookat);
    put_v3(&w, c->vup);
    put_v3(&w, rt_v3(0, 0, 0)); /* reserved */
    put_f64(&w, c->vfov_deg);
    put_f64(&w, c->aperture);
    put_f64(&w, c->focus_dist);
    put_v3(&w, s->sky_bottom);
    put_v3(&w, s->sky_top);
    for (uint32_t i = 0; i < s->n_materials; i++) {
        const rt_material *m = &s->materials[i];
        put_u32(&w, m->kind);
        put_v3(&w, m->albedo);
        put_f64(&w, m->fuzz);
        put_f64(&w, m->ior);
    }
    for (uint32_t i = 0; i < s->n_spheres; i++) {
        const rt_sphere *sp = &s->spheres[i];
        put_v3(&w, sp->center);
        put_f64(&w, sp->radius);
        put_u32(&w, sp->material);
    }
    put_u64(&w, rt_hash_bytes(RT_HASH_INIT, b, n - 8));
    *buf = b;
    *len = n;
    return RT_OK;
}

static int finite3(rt_vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

int rt_scene_deserialize(rt_scene *s, const uint8_t *buf, size_t len)
{
    rt_scene_init(s);
    if (len < HEADER_BYTES + FIXED_BYTES + 8 || memcmp(buf, MAGIC, 8) != 0)
        return RT_EFORMAT;
    reader r = {buf + 8, buf + len, 0};
    uint32_t version = get_u32(&r);
    if (version != RT_SCENE_FORMAT_VERSION)
        return RT_EVERSION;
    uint32_t nm = get_u32(&r), ns = get_u32(&r);
    if (nm > RT_SCENE_MAX_SPHERES || ns > RT_SCENE_MAX_SPHERES)
        return RT_EFORMAT;
    size_t want = HEADER_BYTES + FIXED_BYTES + (size_t)nm * MAT_BYTES + (size_t)ns * SPHERE_BYTES + 8;
    if (len != want)
        return RT_EFORMAT;
    uint64_t sum = 0;
    for (int i = 0; i < 8; i++)
        sum |= (uint64_t)buf[len - 8 + i] << (8 * i);
    if (sum != rt_hash_bytes(RT_HASH_INIT, buf, len - 8))
        return RT_ECHECKSUM;
    rt_camera_desc *c = &s->camera;
    c->lookfrom = get_v3(&r);
    c->lookat = get_v3(&r);
    c->vup = get_v3(&r);
    (void)get_v3(&r);
    c->vfov_deg = get_f64(&r);
    c->aperture = get_f64(&r);
    c->focus_dist = get_f64(&r);
    s->sky_bottom = get_v3(&r);
    s->sky_top = get_v3(&r);
    int st = RT_OK;
    for (uint32_t i = 0; i < nm && !st; i++) {
        rt_material m;
        m.kind = get_u32(&r);
        m.albedo = get_v3(&r);
        m.fuzz = get_f64(&r);
        m.ior = get_f64(&r);
        if (m.kind > RT_MAT_DIELECTRIC || !finite3(m.albedo) || !isfinite(m.fuzz) || !isfinite(m.ior))
            st = RT_EFORMAT;
        else
            st = rt_scene_add_material(s, &m, NULL);
    }
    for (uint32_t i = 0; i < ns && !st; i++) {
        rt_vec3 center = get_v3(&r);
        double radius = get_f64(&r);
        uint32_t mat = get_u32(&r);
        st = finite3(center) ? rt_scene_add_sphere(s, center, radius, mat) : RT_EFORMAT;
        if (st == RT_EINVAL)
            st = RT_EFORMAT;
    }
    if (!st && (r.bad || !finite3(c->lookfrom) || !finite3(c->lookat) || !finite3(c->vup) ||
                !(c->vfov_deg > 0 && c->vfov_deg < 180) || !(c->aperture >= 0) || !(c->focus_dist > 0)))
        st = RT_EFORMAT;
    if (st)
        rt_scene_free(s);
    return st;
}

uint64_t rt_scene_hash(const rt_scene *s)
{
    uint8_t *b;
    size_t n;
    if (rt_scene_serialize(s, &b, &n))
        return 0;
    uint64_t h = rt_hash_bytes(RT_HASH_INIT, b, n);
    free(b);
    return h;
}
