/* scene_book2.c - book 2's additions to a scene: textures, images,
 * emitters and media's materials, quads and boxes, moving spheres, media,
 * all placed through an optional rigid motion (xform.h). */
#include "scene.h"
#include "core_internal.h"

#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "status.h"
#include "xform.h"

static int finite3(rt_vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

/* Room for one more item in a list (RT_LIST), within the format's limit. */
#define LIST_GROW(list) \
    ((list).n >= RT_SCENE_MAX_SPHERES ? RT_EOVERFLOW \
                                      : rt_array_reserve((void **)&(list).items, &(list).cap, (size_t)(list).n + 1, \
                                                         sizeof *(list).items))

rt_material rt_scene_emitter(rt_vec3 emit, int two_sided)
{
    rt_material m = {.kind = RT_MAT_EMITTER, .albedo = rt_v3(0, 0, 0), .ior = 1.0,
                     .flags = two_sided ? RT_MAT_TWO_SIDED : 0u, .emit = emit};
    return m;
}

rt_material rt_scene_isotropic(rt_vec3 albedo)
{
    rt_material m = {.kind = RT_MAT_ISOTROPIC, .albedo = albedo, .ior = 1.0};
    return m;
}

rt_material rt_scene_textured(rt_material m, uint32_t tex)
{
    m.texture = tex + 1;
    return m;
}

int rt_scene_add_texture(rt_scene *s, const rt_texture *t, uint32_t *index)
{
    const uint32_t n = s->tex.textures.n;
    int ok = finite3(t->color) && isfinite(t->scale);
    switch (t->kind) {
    case RT_TEX_SOLID:
        break;
    case RT_TEX_CHECKER: /* cells listed before: no cycle */
        ok = ok && t->scale > 0 && t->even < n && t->odd < n;
        break;
    case RT_TEX_NOISE:
        ok = ok && t->scale > 0 && t->mode <= RT_NOISE_MARBLE;
        break;
    case RT_TEX_IMAGE:
        ok = ok && t->image < s->tex.images.n;
        break;
    default:
        ok = 0;
    }
    if (!ok)
        return RT_EINVAL;
    int st = LIST_GROW(s->tex.textures);
    if (st)
        return st;
    s->tex.textures.items[n] = *t;
    if (index)
        *index = n;
    s->tex.textures.n++;
    return RT_OK;
}

int rt_scene_add_image(rt_scene *s, uint32_t width, uint32_t height, const uint8_t *texels, uint32_t *index)
{
    if (width == 0 || height == 0)
        return RT_EINVAL;
    if ((uint64_t)width * height > RT_SCENE_MAX_IMAGE_PIXELS)
        return RT_EOVERFLOW;
    const size_t bytes = (size_t)width * height * 3;
    int st = LIST_GROW(s->tex.images);
    if (!st)
        st = rt_array_reserve((void **)&s->tex.texels, &s->tex.cap_texels, s->tex.n_texels + bytes, 1);
    if (st)
        return st;
    memcpy(s->tex.texels + s->tex.n_texels, texels, bytes);
    rt_image *im = &s->tex.images.items[s->tex.images.n];
    im->width = width;
    im->height = height;
    im->offset = s->tex.n_texels;
    s->tex.n_texels += bytes;
    if (index)
        *index = s->tex.images.n;
    s->tex.images.n++;
    return RT_OK;
}

/* A quad into list (shapes.quads, or media.hull with material 0). */
static int push_quad(rt_scene *s, int hull, rt_vec3 q, rt_vec3 u, rt_vec3 v, uint32_t material, const rt_xform *x)
{
    if (!finite3(q) || !finite3(u) || !finite3(v) || (!hull && material >= s->n_materials))
        return RT_EINVAL;
    /* no motion: the values as given, bit for bit (-0 included) */
    rt_quad r = {.q = q, .u = u, .v = v, .material = material};
    if (x)
        r = (rt_quad){.q = rt_xform_point(x, q),
                      .u = rt_xform_vector(x, u),
                      .v = rt_xform_vector(x, v),
                      .material = material};
    const rt_vec3 n = rt_v3_cross(r.u, r.v);
    if (!(rt_v3_len2(n) > 0) || !isfinite(rt_v3_len2(n))) /* zero area */
        return RT_EINVAL;
    if (hull) {
        int st = LIST_GROW(s->media.hull);
        if (!st)
            s->media.hull.items[s->media.hull.n++] = r;
        return st;
    }
    int st = LIST_GROW(s->shapes.quads);
    if (!st)
        s->shapes.quads.items[s->shapes.quads.n++] = r;
    return st;
}

int rt_scene_add_quad(rt_scene *s, rt_vec3 q, rt_vec3 u, rt_vec3 v, uint32_t material, const rt_xform *x)
{
    return push_quad(s, 0, q, u, v, material, x);
}

/* The six faces of box a..b, each facing out. */
static int push_box(rt_scene *s, int hull, rt_vec3 a, rt_vec3 b, uint32_t material, const rt_xform *x)
{
    const rt_vec3 lo = rt_v3(fmin(a.x, b.x), fmin(a.y, b.y), fmin(a.z, b.z));
    const rt_vec3 hi = rt_v3(fmax(a.x, b.x), fmax(a.y, b.y), fmax(a.z, b.z));
    const rt_vec3 dx = rt_v3(hi.x - lo.x, 0, 0), dy = rt_v3(0, hi.y - lo.y, 0), dz = rt_v3(0, 0, hi.z - lo.z);
    /* front (-z... the book's order), right, back, left, top, bottom */
    const rt_vec3 q[6] = {{lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, lo.y, lo.z},
                          {lo.x, lo.y, lo.z}, {lo.x, hi.y, hi.z}, {lo.x, lo.y, lo.z}};
    const rt_vec3 u[6] = {dx, rt_v3_neg(dz), rt_v3_neg(dx), dz, dx, dx};
    const rt_vec3 v[6] = {dy, dy, dy, dy, rt_v3_neg(dz), dz};
    int st = RT_OK;
    for (int k = 0; k < 6 && !st; k++)
        st = push_quad(s, hull, q[k], u[k], v[k], material, x);
    return st;
}

int rt_scene_add_box(rt_scene *s, rt_vec3 a, rt_vec3 b, uint32_t material, const rt_xform *x)
{
    return push_box(s, 0, a, b, material, x);
}

/* The frame (1 + index) a sphere of motion x keeps its (u, v) in: 0 for
 * no rotation. The frame maps world directions to the object's. */
static int frame_of(rt_scene *s, const rt_xform *x, uint32_t *frame)
{
    *frame = 0;
    if (!x || rt_xform_no_rotation(x))
        return RT_OK;
    int st = LIST_GROW(s->shapes.frames);
    if (st)
        return st;
    rt_frame *f = &s->shapes.frames.items[s->shapes.frames.n++];
    /* the inverse of a rotation is its transpose */
    f->row[0] = rt_v3(x->row[0].x, x->row[1].x, x->row[2].x);
    f->row[1] = rt_v3(x->row[0].y, x->row[1].y, x->row[2].y);
    f->row[2] = rt_v3(x->row[0].z, x->row[1].z, x->row[2].z);
    *frame = s->shapes.frames.n;
    return RT_OK;
}

int rt_scene_add_sphere_x(rt_scene *s, rt_vec3 center, double radius, uint32_t material, const rt_xform *x)
{
    if (!finite3(center))
        return RT_EINVAL;
    int st = rt_scene_add_sphere(s, x ? rt_xform_point(x, center) : center, radius, material);
    if (!st)
        st = frame_of(s, x, &s->spheres[s->n_spheres - 1].frame);
    return st;
}

int rt_scene_add_mover(rt_scene *s, rt_vec3 c0, rt_vec3 c1, double radius, uint32_t material, const rt_xform *x)
{
    if (!finite3(c0) || !finite3(c1) || !(radius != 0.0) || !isfinite(radius) || material >= s->n_materials)
        return RT_EINVAL;
    uint32_t frame;
    int st = frame_of(s, x, &frame);
    if (!st)
        st = LIST_GROW(s->shapes.movers);
    if (st)
        return st;
    rt_mover m = {.center0 = x ? rt_xform_point(x, c0) : c0,
                  .center1 = x ? rt_xform_point(x, c1) : c1,
                  .radius = radius,
                  .material = material,
                  .frame = frame};
    s->shapes.movers.items[s->shapes.movers.n++] = m;
    return RT_OK;
}

static int push_medium(rt_scene *s, const rt_medium *m)
{
    if (!(m->density > 0) || !isfinite(m->density) || m->material >= s->n_materials)
        return RT_EINVAL;
    if (s->media.media.n >= RT_SCENE_MAX_MEDIA)
        return RT_EOVERFLOW;
    int st = LIST_GROW(s->media.media);
    if (!st)
        s->media.media.items[s->media.media.n++] = *m;
    return st;
}

int rt_scene_add_medium_sphere(rt_scene *s, rt_vec3 center, double radius, double density, uint32_t material)
{
    if (!finite3(center) || !(fabs(radius) > 0) || !isfinite(radius))
        return RT_EINVAL;
    rt_medium m = {.shape = RT_MEDIUM_SPHERE, .center = center, .radius = fabs(radius), .density = density,
                   .material = material};
    return push_medium(s, &m);
}

int rt_scene_add_medium_box(rt_scene *s, rt_vec3 a, rt_vec3 b, double density, uint32_t material,
                            const rt_xform *x)
{
    if (!(density > 0) || !isfinite(density) || material >= s->n_materials)
        return RT_EINVAL;
    rt_medium m = {.shape = RT_MEDIUM_HULL, .first = s->media.hull.n, .count = 6, .density = density,
                   .material = material};
    int st = push_box(s, 1, a, b, 0, x);
    if (st) {
        s->media.hull.n = m.first;
        return st;
    }
    return push_medium(s, &m);
}

/* The corners of quad q, in order. */
static void corners(const rt_quad *q, rt_vec3 c[4])
{
    c[0] = q->q;
    c[1] = rt_v3_add(q->q, q->u);
    c[2] = rt_v3_add(c[1], q->v);
    c[3] = rt_v3_add(q->q, q->v);
}

static int near3(rt_vec3 a, rt_vec3 b, double tol) { return rt_v3_len(rt_v3_sub(a, b)) <= tol; }

int rt_scene_hull_check(const rt_quad *q, uint32_t n)
{
    if (n < 4 || n > 64)
        return RT_EINVAL;
    double size = 0;
    for (uint32_t i = 0; i < n; i++)
        size = fmax(size, fmax(rt_v3_len(q[i].q), fmax(rt_v3_len(q[i].u), rt_v3_len(q[i].v))));
    const double tol = 1e-9 * size; /* rotated corners differ in their last bits */
    for (uint32_t i = 0; i < n; i++) {
        rt_vec3 a[4];
        corners(&q[i], a);
        const rt_vec3 nrm = rt_v3_cross(q[i].u, q[i].v);
        const double len = rt_v3_len(nrm);
        for (int e = 0; e < 4; e++) { /* every edge is another face's edge, either way round */
            int shared = 0;
            for (uint32_t j = 0; j < n && !shared; j++) {
                rt_vec3 b[4];
                corners(&q[j], b);
                for (int f = 0; f < 4 && j != i && !shared; f++)
                    shared = (near3(a[e], b[f], tol) && near3(a[(e + 1) % 4], b[(f + 1) % 4], tol)) ||
                             (near3(a[e], b[(f + 1) % 4], tol) && near3(a[(e + 1) % 4], b[f], tol));
            }
            if (!shared)
                return RT_EINVAL;
        }
        int side = 0; /* convex: every corner on one side of each face's plane */
        for (uint32_t j = 0; j < n; j++) {
            rt_vec3 b[4];
            corners(&q[j], b);
            for (int f = 0; f < 4; f++) {
                const double d = rt_v3_dot(nrm, rt_v3_sub(b[f], q[i].q)) / len;
                const int sd = d > tol ? 1 : d < -tol ? -1 : 0;
                if (sd && side && sd != side)
                    return RT_ERANGE;
                side = sd ? sd : side;
            }
        }
    }
    return RT_OK;
}

int rt_scene_add_medium_hull(rt_scene *s, const rt_quad *quads, uint32_t n, double density, uint32_t material,
                             const rt_xform *x)
{
    if (!(density > 0) || !isfinite(density) || material >= s->n_materials)
        return RT_EINVAL;
    rt_medium m = {.shape = RT_MEDIUM_HULL, .first = s->media.hull.n, .count = n, .density = density,
                   .material = material};
    int st = rt_scene_hull_check(quads, n) ? RT_EINVAL : RT_OK;
    for (uint32_t i = 0; i < n && !st; i++)
        st = push_quad(s, 1, quads[i].q, quads[i].u, quads[i].v, 0, x);
    if (!st)
        st = push_medium(s, &m);
    if (st)
        s->media.hull.n = m.first;
    return st;
}

int rt_scene_is_book2(const rt_scene *s)
{
    for (uint32_t i = 0; i < s->n_materials; i++)
        if (s->materials[i].kind > RT_MAT_DIELECTRIC || s->materials[i].texture)
            return 1;
    return s->shapes.quads.n || s->shapes.movers.n || s->media.media.n || s->tex.textures.n ||
           s->background_kind != RT_BACKGROUND_SKY || s->camera.pixels != RT_PIXELS_SEED;
}
