/* scene_json.c - loading scene files with cJSON (strict: unknown or
 * duplicate fields, wrong types and out-of-range values are refused with
 * the field's path): the file, the camera, the background, the materials
 * and the spheres (book 1's objects); book 2's objects are read by
 * scene_json_book2.c, and scene_json_write.c writes files. */
#include "scene_json.h"
#include "io_internal.h"
#include "scene_json_read.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "camera.h"
#include "fileio.h"
#include "status.h"

#define MAX_SKY 1000.0
#define MAX_IOR 100.0
#define MAX_EMIT 1e6
#define PI 3.14159265358979323846

int rt_scene_files_add(rt_scene_files *f, const char *path)
{
    char *copy = malloc(strlen(path) + 1);
    if (!copy || rt_array_reserve((void **)&f->images, &f->cap, (size_t)f->n + 1, sizeof *f->images)) {
        free(copy);
        return RT_ENOMEM;
    }
    strcpy(copy, path);
    f->images[f->n++] = copy;
    return RT_OK;
}

void rt_scene_files_free(rt_scene_files *f)
{
    for (uint32_t i = 0; i < f->n; i++)
        free(f->images[i]);
    free(f->images);
    memset(f, 0, sizeof *f);
}

/* The lens, given as aperture or as book v4's defocus_angle. */
static int parse_lens(rt_json_ctx *c, const cJSON *cam, rt_camera_desc *d)
{
    const cJSON *aperture = cJSON_GetObjectItemCaseSensitive(cam, "aperture");
    const cJSON *angle = cJSON_GetObjectItemCaseSensitive(cam, "defocus_angle");
    d->aperture = 0.0;
    if (aperture && angle)
        return rt_json_fail(c, RT_EFORMAT, "camera", "give the lens as aperture or as defocus_angle, not both");
    int st = rt_json_opt_number(c, cam, "camera", "aperture", 0.0, RT_JSON_MAX_COORD, RT_JSON_CLOSED, &d->aperture);
    if (!st && angle) {
        /* a cone of this angle with its apex at the focus plane has a base
         * of diameter 2 focus_dist tan(angle / 2) */
        double deg;
        st = rt_json_number(c, angle, "camera.defocus_angle", 0.0, 180.0, RT_JSON_OPEN_HI, &deg);
        if (!st)
            d->aperture = 2.0 * d->focus_dist * tan(deg * PI / 360.0);
    }
    return st;
}

static int parse_camera(rt_json_ctx *c, const cJSON *cam, int version, rt_camera_desc *d)
{
    static const char *const keys[] = {"lookfrom", "lookat",     "vup", "vfov", "aperture", "defocus_angle",
                                       "focus_dist", "pixels", NULL};
    const char *w = "camera";
    int st = rt_json_need_object(c, cam, w);
    if (!st) {
        const char *const *k = keys;
        const char *v1[8];
        if (version == 1) { /* version 1 has no pixels */
            memcpy(v1, keys, sizeof v1);
            v1[7] = NULL;
            k = v1;
        }
        st = rt_json_check_keys(c, cam, w, k);
    }
    if (!st)
        st = rt_json_point(c, cam, w, "lookfrom", &d->lookfrom);
    if (!st)
        st = rt_json_point(c, cam, w, "lookat", &d->lookat);
    if (!st)
        st = rt_json_member_vec3(c, cam, w, "vup", 0, -RT_JSON_MAX_COORD, RT_JSON_MAX_COORD, &d->vup);
    if (!st)
        st = rt_json_opt_number(c, cam, w, "vfov", 0.0, 180.0, RT_JSON_OPEN_LO | RT_JSON_OPEN_HI, &d->vfov_deg);
    if (st)
        return st;
    d->focus_dist = rt_v3_len(rt_v3_sub(d->lookfrom, d->lookat));
    if (d->focus_dist == 0.0)
        return rt_json_fail(c, RT_EFORMAT, "camera.lookat", "equals camera.lookfrom (no view direction)");
    st = rt_json_opt_number(c, cam, w, "focus_dist", 0.0, RT_JSON_MAX_COORD, RT_JSON_OPEN_LO, &d->focus_dist);
    if (!st)
        st = parse_lens(c, cam, d);
    const cJSON *px = cJSON_GetObjectItemCaseSensitive(cam, "pixels");
    if (!st && px) {
        if (cJSON_IsString(px) && !strcmp(px->valuestring, "book1"))
            d->pixels = RT_PIXELS_SEED;
        else if (cJSON_IsString(px) && !strcmp(px->valuestring, "book2"))
            d->pixels = RT_PIXELS_BOOK2;
        else
            return rt_json_fail(c, RT_EFORMAT, "camera.pixels", "expected \"book1\" or \"book2\"");
    }
    rt_camera probe;
    if (!st && rt_camera_init(&probe, d, 1.0) != RT_OK)
        return rt_json_fail(c, RT_EFORMAT, "camera.vup", "zero or parallel to the view direction (lookat - lookfrom)");
    return st;
}

static int parse_background(rt_json_ctx *c, const cJSON *bg, int version, rt_scene *s)
{
    static const char *const keys[] = {"bottom", "top", "color", NULL};
    const char *w = "background";
    int st = rt_json_need_object(c, bg, w);
    if (!st)
        st = rt_json_check_keys(c, bg, w, version == 1 ? (const char *const[]){"bottom", "top", NULL} : keys);
    if (!st)
        st = rt_json_member_vec3(c, bg, w, "bottom", 0, 0.0, MAX_SKY, &s->sky_bottom);
    if (!st)
        st = rt_json_member_vec3(c, bg, w, "top", 0, 0.0, MAX_SKY, &s->sky_top);
    if (!st && cJSON_GetObjectItemCaseSensitive(bg, "color")) {
        s->background_kind = RT_BACKGROUND_COLOR;
        st = rt_json_member_vec3(c, bg, w, "color", 1, 0.0, MAX_SKY, &s->background);
    }
    return st;
}

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
    rt_vec3 col;
    uint32_t tex;
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

static int table_material(rt_json_ctx *c, const cJSON *e, const char *w, const rt_xform *x, int depth,
                          rt_scene *s)
{
    (void)x;
    (void)depth;
    rt_material m;
    int st = rt_json_material(c, e, w, s, &m);
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(e, "name");
    if (!st && name && !cJSON_IsString(name)) {
        char at[200];
        rt_json_join(at, sizeof at, w, "name");
        st = rt_json_fail(c, RT_EFORMAT, at, "expected a string");
    }
    return st ? st : rt_json_add_status(c, rt_scene_add_material(s, &m, NULL), "materials");
}

static int book1_sphere(rt_json_ctx *c, const cJSON *e, const char *w, const rt_xform *x, int depth, rt_scene *s)
{
    (void)depth;
    return rt_json_sphere(c, e, w, x, 0, s);
}

/* "noise_seed": an integer to 2^53, or a string of decimal digits. */
static int parse_noise_seed(rt_json_ctx *c, const cJSON *item, rt_scene *s)
{
    if (cJSON_IsString(item)) {
        const char *p = item->valuestring;
        char *end;
        errno = 0;
        unsigned long long v = strtoull(p, &end, 10);
        if (*p < '0' || *p > '9' || *end || errno)
            return rt_json_fail(c, RT_EFORMAT, "noise_seed", "expected an integer from 0 to 2^64 - 1");
        s->tex.noise_seed = v;
        return RT_OK;
    }
    double v;
    int st = rt_json_number(c, item, "noise_seed", 0, 9007199254740992.0, RT_JSON_CLOSED, &v);
    if (!st && v != floor(v))
        st = rt_json_fail(c, RT_EFORMAT, "noise_seed", "expected an integer");
    if (!st)
        s->tex.noise_seed = (uint64_t)v;
    return st;
}

static int parse_root(rt_json_ctx *c, const cJSON *root, rt_scene *s)
{
    static const char *const keys1[] = {"version", "camera", "background", "materials", "spheres", NULL};
    static const char *const keys2[] = {"version",  "camera", "background", "noise_seed", "textures", "materials",
                                        "frames",   "groups", "spheres",    "moving_spheres", "quads", "boxes",
                                        "media",    "instances", NULL};
    if (!cJSON_IsObject(root))
        return rt_json_fail(c, RT_EFORMAT, "", "expected a JSON object at the top level");
    const cJSON *version = cJSON_GetObjectItemCaseSensitive(root, "version");
    c->version = 1;
    if (version && cJSON_IsNumber(version) && version->valuedouble == 2)
        c->version = 2;
    int st = rt_json_check_keys(c, root, "", c->version == 1 ? keys1 : keys2);
    if (!st && version && !(cJSON_IsNumber(version) && (version->valuedouble == 1 || version->valuedouble == 2)))
        st = rt_json_fail(c, RT_EFORMAT, "version", "this program reads versions 1 and 2");
    if (!st)
        st = parse_camera(c, cJSON_GetObjectItemCaseSensitive(root, "camera"), c->version, &s->camera);
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(root, "background");
    if (!st && item)
        st = parse_background(c, item, c->version, s);
    item = cJSON_GetObjectItemCaseSensitive(root, "noise_seed");
    if (!st && item)
        st = parse_noise_seed(c, item, s);
    item = cJSON_GetObjectItemCaseSensitive(root, "textures");
    if (!st && item)
        st = rt_json_textures(c, item, s);
    item = cJSON_GetObjectItemCaseSensitive(root, "materials");
    if (!st && item)
        st = rt_json_each(c, item, "", "materials", table_material, NULL, 0, s);
    c->n_table = s->n_materials; /* objects refer to these; their inline materials come after */
    item = cJSON_GetObjectItemCaseSensitive(root, "frames");
    if (!st && item)
        st = rt_json_frames(c, item, s);
    c->n_frames = s->shapes.frames.n;
    if (c->version == 1) { /* spheres only, and required */
        const cJSON *spheres = cJSON_GetObjectItemCaseSensitive(root, "spheres");
        if (!st && !spheres)
            st = rt_json_fail(c, RT_EFORMAT, "spheres", "missing");
        return st ? st : rt_json_each(c, spheres, "", "spheres", book1_sphere, NULL, 0, s);
    }
    return st ? st : rt_json_objects(c, root, "", NULL, 0, s);
}

static void line_col(const char *text, size_t len, size_t pos, unsigned *line, unsigned *col)
{
    *line = 1;
    *col = 1;
    for (size_t i = 0; i < pos && i < len; i++) {
        if (text[i] == '\n') {
            ++*line;
            *col = 1;
        } else {
            ++*col;
        }
    }
}

int rt_scene_json_parse(rt_scene *s, const char *text, size_t len, const char *name, const char *dir,
                        rt_scene_files *files, char *err, size_t errlen)
{
    rt_scene_files own = {NULL, 0, 0};
    rt_json_ctx c = {.name = name, .err = err, .errlen = errlen, .dir = dir, .files = files ? files : &own};
    rt_scene_init(s);
    if (errlen)
        err[0] = 0;
    const char *end = NULL;
    cJSON *root = len ? cJSON_ParseWithLengthOpts(text, len, &end, 0) : NULL;
    size_t pos = 0;
    if (root) {
        pos = (size_t)(end - text);
        while (pos < len && (text[pos] == ' ' || text[pos] == '\t' || text[pos] == '\n' || text[pos] == '\r'))
            pos++;
    } else if (end && end >= text && end <= text + len) {
        pos = (size_t)(end - text);
    }
    if (!root || pos < len) {
        unsigned line, col;
        line_col(text, len, pos, &line, &col);
        char where[64];
        snprintf(where, sizeof where, "line %u, column %u", line, col);
        int st = rt_json_fail(&c, RT_EFORMAT, where,
                              !len ? "empty file" : root ? "unexpected text after the JSON value" : "invalid JSON");
        cJSON_Delete(root);
        return st;
    }
    c.root = root;
    int st = parse_root(&c, root, s);
    cJSON_Delete(root);
    if (st) {
        rt_scene_free(s);
        rt_scene_files_free(c.files);
    }
    rt_scene_files_free(&own);
    return st;
}

int rt_scene_json_load(rt_scene *s, const char *path, rt_scene_files *files, char *err, size_t errlen)
{
    rt_json_ctx c = {.name = path, .err = err, .errlen = errlen};
    rt_scene_init(s); /* valid (empty) also when the file cannot be read */
    char *buf;
    size_t n;
    int st = rt_file_read_all(path, RT_SCENE_JSON_MAX_BYTES, &buf, &n);
    if (st == RT_EOVERFLOW)
        return rt_json_fail(&c, st, "", "larger than %u MiB", RT_SCENE_JSON_MAX_BYTES >> 20);
    if (st == RT_EIO)
        return rt_json_fail(&c, st, "", "cannot read: %s", strerror(errno));
    if (st)
        return rt_json_fail(&c, st, "", "%s", rt_status_str(st));
    /* image paths are relative to the file's directory */
    char *dir = malloc(strlen(path) + 2);
    if (!dir) {
        free(buf);
        return rt_json_fail(&c, RT_ENOMEM, "", "out of memory");
    }
    strcpy(dir, path);
    char *slash = strrchr(dir, '/');
    if (slash)
        slash[slash == dir] = 0; /* "/a.json" -> "/" */
    else
        strcpy(dir, ".");
    st = rt_scene_json_parse(s, buf, n, path, dir, files, err, errlen);
    free(dir);
    free(buf);
    return st;
}
