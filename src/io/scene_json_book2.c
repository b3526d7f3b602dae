/* scene_json_book2.c - reading book 2's part of a scene file: textures
 * (images read relative to the file), a dump's frames, and the object
 * lists (quads, boxes, moving spheres, media, groups and instances). */
#include "scene_json_read.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "status.h"
#include "texture_image.h"

#define MAX_SCALE 1e6
#define MAX_DENSITY 1e12

/* The image at path (relative to c->dir) as *index, read once per path. */
static int image_file(rt_json_ctx *c, const cJSON *p, const char *at, rt_scene *s, uint32_t *index)
{
    if (!cJSON_IsString(p) || !p->valuestring[0])
        return rt_json_fail(c, RT_EFORMAT, at, p ? "expected a file name" : "missing");
    if (!c->dir)
        return rt_json_fail(c, RT_EFORMAT, at, "image textures are read from files only");
    const char *rel = p->valuestring;
    char path[4096];
    if (snprintf(path, sizeof path, "%s%s%s", rel[0] == '/' ? "" : c->dir, rel[0] == '/' ? "" : "/", rel) >=
        (int)sizeof path)
        return rt_json_fail(c, RT_EFORMAT, at, "path too long");
    for (uint32_t i = 0; i < c->files->n; i++)
        if (!strcmp(c->files->images[i], path)) {
            *index = i;
            return RT_OK;
        }
    rt_texture_image img;
    int st = rt_texture_image_load(path, NULL, &img);
    if (st)
        return rt_json_fail(c, st, at, "%s: %s", path, rt_status_str(st));
    st = rt_scene_add_image(s, img.width, img.height, img.texels, index);
    rt_texture_image_free(&img);
    if (!st && *index != c->files->n) /* images come from files only */
        st = RT_EINVAL;
    if (!st)
        st = rt_scene_files_add(c->files, path);
    return rt_json_add_status(c, st, at);
}

static int noise_mode(const char *type)
{
    return !strcmp(type, "noise") ? RT_NOISE_PLAIN : !strcmp(type, "turbulence") ? RT_NOISE_TURB
                                                     : !strcmp(type, "marble")   ? RT_NOISE_MARBLE
                                                                                 : -1;
}

static int parse_texture(rt_json_ctx *c, const cJSON *obj, const char *w, rt_scene *s)
{
    static const char *const solid_keys[] = {"type", "name", "color", NULL};
    static const char *const checker_keys[] = {"type", "name", "scale", "even", "odd", NULL};
    static const char *const noise_keys[] = {"type", "name", "scale", "color", NULL};
    static const char *const image_keys[] = {"type", "name", "path", NULL};
    int st = rt_json_need_object(c, obj, w);
    if (st)
        return st;
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(obj, "type"), *name = cJSON_GetObjectItemCaseSensitive(obj, "name");
    char at[200];
    rt_json_join(at, sizeof at, w, "type");
    if (!cJSON_IsString(type))
        return rt_json_fail(c, RT_EFORMAT, at, type ? "expected a string" : "missing");
    if (name && !cJSON_IsString(name)) {
        rt_json_join(at, sizeof at, w, "name");
        return rt_json_fail(c, RT_EFORMAT, at, "expected a string");
    }
    const char *t = type->valuestring;
    const uint32_t n = s->tex.textures.n; /* a checker's cells come before it */
    rt_texture tex = {.kind = RT_TEX_SOLID};
    if (!strcmp(t, "solid")) {
        st = rt_json_check_keys(c, obj, w, solid_keys);
        if (!st)
            st = rt_json_member_vec3(c, obj, w, "color", 1, 0.0, 1.0, &tex.color);
    } else if (!strcmp(t, "checker")) {
        tex.kind = RT_TEX_CHECKER;
        st = rt_json_check_keys(c, obj, w, checker_keys);
        if (!st)
            st = rt_json_req_number(c, obj, w, "scale", 0.0, MAX_SCALE, RT_JSON_OPEN_LO, &tex.scale);
        rt_json_join(at, sizeof at, w, "even");
        if (!st)
            st = rt_json_ref(c, cJSON_GetObjectItemCaseSensitive(obj, "even"), at, "textures", n, &tex.even);
        rt_json_join(at, sizeof at, w, "odd");
        if (!st)
            st = rt_json_ref(c, cJSON_GetObjectItemCaseSensitive(obj, "odd"), at, "textures", n, &tex.odd);
    } else if (noise_mode(t) >= 0) {
        tex.kind = RT_TEX_NOISE;
        tex.mode = (uint32_t)noise_mode(t);
        tex.color = rt_v3(1, 1, 1);
        st = rt_json_check_keys(c, obj, w, noise_keys);
        if (!st)
            st = rt_json_req_number(c, obj, w, "scale", 0.0, MAX_SCALE, RT_JSON_OPEN_LO, &tex.scale);
        if (!st)
            st = rt_json_member_vec3(c, obj, w, "color", 0, 0.0, 1.0, &tex.color);
    } else if (!strcmp(t, "image")) {
        tex.kind = RT_TEX_IMAGE;
        st = rt_json_check_keys(c, obj, w, image_keys);
        rt_json_join(at, sizeof at, w, "path");
        if (!st)
            st = image_file(c, cJSON_GetObjectItemCaseSensitive(obj, "path"), at, s, &tex.image);
    } else {
        char q[48];
        rt_json_quote(t, q, sizeof q);
        return rt_json_fail(c, RT_EFORMAT, at, "'%s' is not one of solid, checker, noise, turbulence, marble, image",
                            q);
    }
    return st ? st : rt_json_add_status(c, rt_scene_add_texture(s, &tex, NULL), w);
}

static int texture_elem(rt_json_ctx *c, const cJSON *e, const char *w, const rt_xform *x, int depth, rt_scene *s)
{
    (void)x;
    (void)depth;
    return parse_texture(c, e, w, s);
}

int rt_json_textures(rt_json_ctx *c, const cJSON *arr, rt_scene *s)
{
    return rt_json_each(c, arr, "", "textures", texture_elem, NULL, 0, s);
}

static int frame_elem(rt_json_ctx *c, const cJSON *e, const char *w, const rt_xform *x, int depth, rt_scene *s)
{
    (void)x;
    (void)depth;
    rt_frame f;
    if (!cJSON_IsArray(e) || cJSON_GetArraySize(e) != 3)
        return rt_json_fail(c, RT_EFORMAT, w, "expected 3 rows of 3 numbers");
    for (int k = 0; k < 3; k++) {
        char at[240];
        snprintf(at, sizeof at, "%s[%d]", w, k);
        int st = rt_json_vec3(c, cJSON_GetArrayItem(e, k), at, -1.0, 1.0, &f.row[k]);
        if (st)
            return st;
    }
    const double det = rt_v3_dot(f.row[0], rt_v3_cross(f.row[1], f.row[2]));
    if (!(fabs(det - 1.0) < 1e-6))
        return rt_json_fail(c, RT_EFORMAT, w, "not a rotation (determinant %.17g)", det);
    if (s->shapes.frames.n >= RT_SCENE_MAX_SPHERES)
        return rt_json_add_status(c, RT_EOVERFLOW, "frames");
    if (rt_array_reserve((void **)&s->shapes.frames.items, &s->shapes.frames.cap, (size_t)s->shapes.frames.n + 1,
                         sizeof f))
        return rt_json_fail(c, RT_ENOMEM, w, "out of memory");
    s->shapes.frames.items[s->shapes.frames.n++] = f;
    return RT_OK;
}

int rt_json_frames(rt_json_ctx *c, const cJSON *arr, rt_scene *s)
{
    return rt_json_each(c, arr, "", "frames", frame_elem, NULL, 0, s);
}

static int sphere_elem(rt_json_ctx *c, const cJSON *e, const char *w, const rt_xform *x, int depth, rt_scene *s)
{
    (void)depth;
    return rt_json_sphere(c, e, w, x, 0, s);
}

static int mover_elem(rt_json_ctx *c, const cJSON *e, const char *w, const rt_xform *x, int depth, rt_scene *s)
{
    (void)depth;
    return rt_json_sphere(c, e, w, x, 1, s);
}

/* obj's material reference (key "material"), checked to be of kind. */
static int material_of(rt_json_ctx *c, const cJSON *obj, const char *w, rt_scene *s, uint32_t *index)
{
    char at[200];
    rt_json_join(at, sizeof at, w, "material");
    return rt_json_material_ref(c, cJSON_GetObjectItemCaseSensitive(obj, "material"), at, s, index);
}

/* A quad's q, u, v (with a message for one of no area). */
static int quad_vectors(rt_json_ctx *c, const cJSON *obj, const char *w, rt_quad *q)
{
    int st = rt_json_point(c, obj, w, "q", &q->q);
    if (!st)
        st = rt_json_point(c, obj, w, "u", &q->u);
    if (!st)
        st = rt_json_point(c, obj, w, "v", &q->v);
    if (!st && !(rt_v3_len2(rt_v3_cross(q->u, q->v)) > 0))
        st = rt_json_fail(c, RT_EFORMAT, w, "degenerate quad: u and v span no area (u x v = 0)");
    return st;
}

static int quad_elem(rt_json_ctx *c, const cJSON *e, const char *w, const rt_xform *x, int depth, rt_scene *s)
{
    static const char *const keys[] = {"q", "u", "v", "material", NULL};
    (void)depth;
    rt_quad q;
    int st = rt_json_need_object(c, e, w);
    if (!st)
        st = rt_json_check_keys(c, e, w, keys);
    if (!st)
        st = quad_vectors(c, e, w, &q);
    if (!st)
        st = material_of(c, e, w, s, &q.material);
    return st ? st : rt_json_add_status(c, rt_scene_add_quad(s, q.q, q.u, q.v, q.material, x), w);
}

/* A box's corners min and max, min below max on every axis. */
static int box_corners(rt_json_ctx *c, const cJSON *obj, const char *w, rt_vec3 *lo, rt_vec3 *hi)
{
    int st = rt_json_point(c, obj, w, "min", lo);
    if (!st)
        st = rt_json_point(c, obj, w, "max", hi);
    if (!st && !(lo->x < hi->x && lo->y < hi->y && lo->z < hi->z))
        st = rt_json_fail(c, RT_EFORMAT, w, "degenerate box: min must be below max on every axis");
    return st;
}

static int box_elem(rt_json_ctx *c, const cJSON *e, const char *w, const rt_xform *x, int depth, rt_scene *s)
{
    static const char *const keys[] = {"min", "max", "material", NULL};
    (void)depth;
    rt_vec3 lo, hi;
    uint32_t m;
    int st = rt_json_need_object(c, e, w);
    if (!st)
        st = rt_json_check_keys(c, e, w, keys);
    if (!st)
        st = box_corners(c, e, w, &lo, &hi);
    if (!st)
        st = material_of(c, e, w, s, &m);
    return st ? st : rt_json_add_status(c, rt_scene_add_box(s, lo, hi, m, x), w);
}

/* A medium's hull: an array of quads bounding a closed convex body. */
static int medium_hull(rt_json_ctx *c, const cJSON *arr, const char *w, double density, uint32_t m,
                       const rt_xform *x, rt_scene *s)
{
    static const char *const keys[] = {"q", "u", "v", NULL};
    rt_quad q[64];
    uint32_t n = 0;
    char at[200];
    rt_json_join(at, sizeof at, w, "hull");
    if (!cJSON_IsArray(arr) || cJSON_GetArraySize(arr) < 4 || cJSON_GetArraySize(arr) > 64)
        return rt_json_fail(c, RT_EFORMAT, at, "expected an array of 4 to 64 quads");
    const cJSON *e;
    cJSON_ArrayForEach(e, arr)
    {
        char qw[240];
        snprintf(qw, sizeof qw, "%s[%u]", at, n);
        int st = rt_json_need_object(c, e, qw);
        if (!st)
            st = rt_json_check_keys(c, e, qw, keys);
        if (!st)
            st = quad_vectors(c, e, qw, &q[n]);
        if (st)
            return st;
        q[n++].material = 0;
    }
    int st = rt_scene_hull_check(q, n);
    if (st == RT_ERANGE)
        return rt_json_fail(c, RT_EFORMAT, at, "the boundary is not convex");
    if (st)
        return rt_json_fail(c, RT_EFORMAT, at, "the boundary is open (an edge of a quad is no other quad's edge)");
    return rt_json_add_status(c, rt_scene_add_medium_hull(s, q, n, density, m, x), w);
}

static int medium_elem(rt_json_ctx *c, const cJSON *e, const char *w, const rt_xform *x, int depth, rt_scene *s)
{
    static const char *const keys[] = {"sphere", "box", "hull", "density", "material", NULL};
    static const char *const sphere_keys[] = {"center", "radius", NULL};
    static const char *const box_keys[] = {"min", "max", NULL};
    (void)depth;
    int st = rt_json_need_object(c, e, w);
    if (!st)
        st = rt_json_check_keys(c, e, w, keys);
    if (st)
        return st;
    const cJSON *sp = cJSON_GetObjectItemCaseSensitive(e, "sphere"), *box = cJSON_GetObjectItemCaseSensitive(e, "box"),
                *hull = cJSON_GetObjectItemCaseSensitive(e, "hull");
    if (!!sp + !!box + !!hull != 1)
        return rt_json_fail(c, RT_EFORMAT, w, "give the boundary as one of sphere, box, hull");
    double density;
    uint32_t m;
    st = rt_json_req_number(c, e, w, "density", 0.0, MAX_DENSITY, RT_JSON_OPEN_LO, &density);
    if (!st)
        st = material_of(c, e, w, s, &m);
    if (!st && s->materials[m].kind != RT_MAT_ISOTROPIC)
        st = rt_json_fail(c, RT_EFORMAT, w, "a medium's material must be isotropic");
    if (st || hull)
        return st ? st : medium_hull(c, hull, w, density, m, x, s);
    char at[200];
    rt_json_join(at, sizeof at, w, sp ? "sphere" : "box");
    st = rt_json_need_object(c, sp ? sp : box, at);
    if (!st)
        st = rt_json_check_keys(c, sp ? sp : box, at, sp ? sphere_keys : box_keys);
    if (st || !sp) {
        rt_vec3 lo, hi;
        if (!st)
            st = box_corners(c, box, at, &lo, &hi);
        return st ? st : rt_json_add_status(c, rt_scene_add_medium_box(s, lo, hi, density, m, x), w);
    }
    rt_vec3 center;
    double r;
    st = rt_json_point(c, sp, at, "center", &center);
    if (!st)
        st = rt_json_req_number(c, sp, at, "radius", 0.0, RT_JSON_MAX_COORD, RT_JSON_OPEN_LO, &r);
    if (!st && s->media.media.n >= RT_SCENE_MAX_MEDIA)
        return rt_json_fail(c, RT_EOVERFLOW, w, "more than %u media", RT_SCENE_MAX_MEDIA);
    if (!st && x)
        center = rt_xform_point(x, center);
    return st ? st : rt_json_add_status(c, rt_scene_add_medium_sphere(s, center, r, density, m), w);
}

static const char *const OBJECT_LISTS[] = {"spheres", "moving_spheres", "quads", "boxes", "media", "instances", NULL};

/* The instance's transform: rotate_y degrees, then translate. */
static int instance_xform(rt_json_ctx *c, const cJSON *e, const char *w, const rt_xform *outer, rt_xform *x)
{
    double deg = 0;
    rt_vec3 t = rt_v3(0, 0, 0);
    int st = rt_json_opt_number(c, e, w, "rotate_y", -360.0, 360.0, RT_JSON_CLOSED, &deg);
    if (!st)
        st = rt_json_member_vec3(c, e, w, "translate", 0, -RT_JSON_MAX_COORD, RT_JSON_MAX_COORD, &t);
    const rt_xform r = rt_xform_rotate_y(deg), tr = rt_xform_translate(t);
    *x = rt_xform_then(&r, &tr);
    if (outer)
        *x = rt_xform_then(x, outer);
    return st;
}

static int instance_elem(rt_json_ctx *c, const cJSON *e, const char *w, const rt_xform *outer, int depth,
                         rt_scene *s)
{
    static const char *const keys[] = {"group", "objects", "rotate_y", "translate", NULL};
    int st = rt_json_need_object(c, e, w);
    if (!st)
        st = rt_json_check_keys(c, e, w, keys);
    if (st)
        return st;
    if (depth >= RT_JSON_MAX_NESTING)
        return rt_json_fail(c, RT_EFORMAT, w, "instances nested deeper than %d (a group that contains itself?)",
                            RT_JSON_MAX_NESTING);
    const cJSON *g = cJSON_GetObjectItemCaseSensitive(e, "group"), *of = cJSON_GetObjectItemCaseSensitive(e, "objects");
    char at[200];
    rt_json_join(at, sizeof at, w, g ? "group" : "objects");
    if (!!g == !!of)
        return rt_json_fail(c, RT_EFORMAT, w, "give what to place as group or as objects, one of them");
    if (g) {
        if (!cJSON_IsString(g))
            return rt_json_fail(c, RT_EFORMAT, at, "expected a group's name");
        of = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(c->root, "groups"), g->valuestring);
        if (!of) {
            char q[48];
            rt_json_quote(g->valuestring, q, sizeof q);
            return rt_json_fail(c, RT_EFORMAT, at, "no group named '%s'", q);
        }
    }
    st = rt_json_need_object(c, of, at);
    if (!st)
        st = rt_json_check_keys(c, of, at, OBJECT_LISTS);
    int n = 0;
    for (const char *const *k = OBJECT_LISTS; *k; k++)
        n += cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(of, *k));
    if (!st && n == 0)
        return rt_json_fail(c, RT_EFORMAT, at, "instance of nothing (no objects)");
    rt_xform x;
    if (!st)
        st = instance_xform(c, e, w, outer, &x);
    return st ? st : rt_json_objects(c, of, at, &x, depth + 1, s);
}

/* The top level's groups: objects each (read where instanced). */
static int check_groups(rt_json_ctx *c, const cJSON *groups)
{
    int st = rt_json_need_object(c, groups, "groups");
    if (st) /* an array's items have no names to quote */
        return st;
    const cJSON *g;
    cJSON_ArrayForEach(g, groups)
    {
        char q[48], at[80];
        rt_json_quote(g->string, q, sizeof q);
        rt_json_join(at, sizeof at, "groups", q);
        if (!st)
            st = rt_json_need_object(c, g, at);
        if (!st)
            st = rt_json_check_keys(c, g, at, OBJECT_LISTS);
    }
    for (const cJSON *a = groups->child; a && !st; a = a->next)
        for (const cJSON *b = a->next; b && !st; b = b->next)
            if (!strcmp(a->string, b->string))
                st = rt_json_fail(c, RT_EFORMAT, "groups", "two groups of one name");
    return st;
}

int rt_json_objects(rt_json_ctx *c, const cJSON *obj, const char *where, const rt_xform *x, int depth, rt_scene *s)
{
    static const rt_json_elem_fn fns[] = {sphere_elem, mover_elem, quad_elem, box_elem, medium_elem, instance_elem};
    const cJSON *groups = cJSON_GetObjectItemCaseSensitive(obj, "groups");
    int st = depth == 0 && groups ? check_groups(c, groups) : RT_OK;
    for (int k = 0; OBJECT_LISTS[k] && !st; k++) {
        const cJSON *arr = cJSON_GetObjectItemCaseSensitive(obj, OBJECT_LISTS[k]);
        if (arr)
            st = rt_json_each(c, arr, where, OBJECT_LISTS[k], fns[k], x, depth, s);
    }
    return st;
}
