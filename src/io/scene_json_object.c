/* scene_json_object.c - a scene file's materials (book 1's and book 2's:
 * colours or textures, emitters, isotropic media) and spheres (still or
 * moving, in an instance's frame), read for scene_json.c's tables and
 * scene_json_book2.c's objects. */
#include "io_internal.h"
#include "scene_json_read.h"

#include <math.h>
#include <string.h>

#include "status.h"

#define MAX_IOR 100.0
#define MAX_EMIT 1e6

/* A colour (key) or a texture, exactly one of them: *tex 1 + index, or 0. */
static int colour_or_texture(rt_json_ctx *c, const cJSON *obj, const char *w, const char *key, double hi,
                             const rt_scene *s, rt_vec3 *colour, uint32_t *tex)
{
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(obj, "texture");
    char at[200];
    *tex = 0;
    *colour = rt_v3(0, 0, 0);
    if (!t)
        return rt_json_member_vec3(c, obj, w, key, 1, 0.0, hi, colour);
    if (cJSON_GetObjectItemCaseSensitive(obj, key))
        return rt_json_fail(c, RT_EFORMAT, w, "give %s or texture, not both", key);
    rt_json_join(at, sizeof at, w, "texture");
    int st = rt_json_ref(c, t, at, "textures", s->tex.textures.n, tex);
    *tex += 1;
    return st;
}

/* The kinds of book 2 (textured lambertian, emitter, isotropic). */
static int parse_material2(rt_json_ctx *c, const cJSON *obj, const char *w, const char *type, rt_scene *s,
                           rt_material *m)
{
    static const char *const lam_keys[] = {"type", "name", "albedo", "texture", NULL};
    static const char *const light_keys[] = {"type", "name", "emit", "texture", "two_sided", NULL};
    rt_vec3 col = {0, 0, 0};
    uint32_t tex = 0; /* both read (and dropped) on an error too */
    int st;
    if (!strcmp(type, "lambertian") || !strcmp(type, "isotropic")) {
        st = rt_json_check_keys(c, obj, w, lam_keys);
        if (!st)
            st = colour_or_texture(c, obj, w, "albedo", 1.0, s, &col, &tex);
        *m = type[0] == 'l' ? rt_scene_lambertian(col) : rt_scene_isotropic(col);
    } else {
        st = rt_json_check_keys(c, obj, w, light_keys);
        if (!st)
            st = colour_or_texture(c, obj, w, "emit", MAX_EMIT, s, &col, &tex);
        const cJSON *two = cJSON_GetObjectItemCaseSensitive(obj, "two_sided");
        if (!st && two && !cJSON_IsBool(two)) {
            char at[200];
            rt_json_join(at, sizeof at, w, "two_sided");
            st = rt_json_fail(c, RT_EFORMAT, at, "expected true or false");
        }
        *m = rt_scene_emitter(col, !two || cJSON_IsTrue(two));
    }
    if (tex)
        *m = rt_scene_textured(*m, tex - 1);
    return st;
}

int rt_json_material(rt_json_ctx *c, const cJSON *obj, const char *w, rt_scene *s, rt_material *m)
{
    static const char *const lam_keys[] = {"type", "name", "albedo", NULL};
    static const char *const metal_keys[] = {"type", "name", "albedo", "fuzz", NULL};
    static const char *const glass_keys[] = {"type", "name", "ior", NULL};
    int st = rt_json_need_object(c, obj, w);
    if (st)
        return st;
    char at[200];
    rt_json_join(at, sizeof at, w, "type");
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(obj, "type");
    if (!type)
        return rt_json_fail(c, RT_EFORMAT, at, "missing");
    if (!cJSON_IsString(type))
        return rt_json_fail(c, RT_EFORMAT, at, "expected a string");
    const char *t = type->valuestring;
    const int v2 = c->version >= 2;
    rt_vec3 albedo = rt_v3(0, 0, 0);
    if (v2 && (!strcmp(t, "lambertian") || !strcmp(t, "isotropic") || !strcmp(t, "emitter"))) {
        st = parse_material2(c, obj, w, t, s, m);
    } else if (!strcmp(t, "lambertian")) {
        st = rt_json_check_keys(c, obj, w, lam_keys);
        if (!st)
            st = rt_json_member_vec3(c, obj, w, "albedo", 1, 0.0, 1.0, &albedo);
        *m = rt_scene_lambertian(albedo);
    } else if (!strcmp(t, "metal")) {
        double fuzz = 0.0;
        st = rt_json_check_keys(c, obj, w, metal_keys);
        if (!st)
            st = rt_json_member_vec3(c, obj, w, "albedo", 1, 0.0, 1.0, &albedo);
        if (!st)
            st = rt_json_opt_number(c, obj, w, "fuzz", 0.0, 1.0, RT_JSON_CLOSED, &fuzz);
        *m = rt_scene_metal(albedo, fuzz);
    } else if (!strcmp(t, "dielectric")) {
        double ior = 0.0;
        st = rt_json_check_keys(c, obj, w, glass_keys);
        if (!st)
            st = rt_json_req_number(c, obj, w, "ior", 0.0, MAX_IOR, RT_JSON_OPEN_LO, &ior);
        *m = rt_scene_dielectric(ior);
    } else {
        char q[48];
        rt_json_quote(t, q, sizeof q);
        return rt_json_fail(c, RT_EFORMAT, at, "'%s' is not one of lambertian, metal, dielectric%s", q,
                            v2 ? ", emitter, isotropic" : "");
    }
    return st;
}

/* A sphere's "frame": 1 + an index into the top level's frames. */
static int sphere_frame(rt_json_ctx *c, const cJSON *obj, const char *w, const rt_xform *x, uint32_t *frame)
{
    const cJSON *f = cJSON_GetObjectItemCaseSensitive(obj, "frame");
    char at[200];
    rt_json_join(at, sizeof at, w, "frame");
    *frame = 0;
    if (!f)
        return RT_OK;
    if (x)
        return rt_json_fail(c, RT_EFORMAT, at, "only at the top level (an instance makes its own frames)");
    int st = rt_json_ref(c, f, at, "frames", c->n_frames, frame);
    if (!st && cJSON_IsString(f))
        return rt_json_fail(c, RT_EFORMAT, at, "expected an index into frames");
    *frame += 1;
    return st;
}

int rt_json_sphere(rt_json_ctx *c, const cJSON *obj, const char *w, const rt_xform *x, int moving, rt_scene *s)
{
    static const char *const keys1[] = {"center", "radius", "material", NULL};
    static const char *const keys2[] = {"center", "radius", "material", "frame", NULL};
    static const char *const keys_mov[] = {"center0", "center1", "radius", "material", "frame", NULL};
    int st = rt_json_need_object(c, obj, w);
    if (!st)
        st = rt_json_check_keys(c, obj, w, moving ? keys_mov : c->version == 1 ? keys1 : keys2);
    rt_vec3 c0, c1 = rt_v3(0, 0, 0);
    double radius;
    if (!st)
        st = rt_json_point(c, obj, w, moving ? "center0" : "center", &c0);
    if (!st && moving)
        st = rt_json_point(c, obj, w, "center1", &c1);
    char at[200];
    rt_json_join(at, sizeof at, w, "radius");
    if (!st)
        st = rt_json_number(c, cJSON_GetObjectItemCaseSensitive(obj, "radius"), at, -RT_JSON_MAX_COORD,
                            RT_JSON_MAX_COORD, RT_JSON_CLOSED, &radius);
    if (!st && radius == 0.0)
        st = rt_json_fail(c, RT_EFORMAT, at, "must not be 0 (a negative radius makes a hollow sphere)");
    uint32_t frame = 0, index;
    if (!st)
        st = sphere_frame(c, obj, w, x, &frame);
    rt_json_join(at, sizeof at, w, "material");
    const cJSON *mat = cJSON_GetObjectItemCaseSensitive(obj, "material");
    if (!st && !mat)
        st = rt_json_fail(c, RT_EFORMAT, at, "missing");
    if (!st && !cJSON_IsNumber(mat) && !cJSON_IsObject(mat) && (c->version == 1 || !cJSON_IsString(mat)))
        st = rt_json_fail(c, RT_EFORMAT, at, "expected an index into materials%s or a material object",
                          c->version == 1 ? "" : ", a name");
    if (!st)
        st = rt_json_material_ref(c, mat, at, s, &index);
    if (st)
        return st;
    if (moving) {
        st = rt_json_add_status(c, rt_scene_add_mover(s, c0, c1, radius, index, x), w);
        if (!st && frame)
            s->shapes.movers.items[s->shapes.movers.n - 1].frame = frame;
        return st;
    }
    st = rt_json_add_status(c, x ? rt_scene_add_sphere_x(s, c0, radius, index, x)
                                 : rt_scene_add_sphere(s, c0, radius, index),
                            "spheres");
    if (!st && frame)
        s->spheres[s->n_spheres - 1].frame = frame;
    return st;
}

int rt_json_material_ref(rt_json_ctx *c, const cJSON *ref, const char *where, rt_scene *s, uint32_t *index)
{
    if (!cJSON_IsObject(ref))
        return rt_json_ref(c, ref, where, "materials", c->n_table, index);
    rt_material m;
    int st = rt_json_material(c, ref, where, s, &m);
    return st ? st : rt_json_add_status(c, rt_scene_add_material(s, &m, index), "materials");
}
