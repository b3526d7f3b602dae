/* scene_json.c - loading scene files with cJSON (strict: unknown or
 * duplicate fields, wrong types and out-of-range values are refused with
 * the field's path): the file, the camera, the background and the tables;
 * materials and spheres are read by scene_json_object.c, book 2's objects by
 * scene_json_book2.c, and scene_json_write.c writes files. */
#include "scene_json.h"
#include "io_internal.h"
#include "scene_json_read.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "anim.h"
#include "array.h"
#include "camera.h"
#include "fileio.h"
#include "status.h"

#define MAX_SKY 1000.0
#define PI 3.14159265358979323846

/* The lens, given as aperture or as book v4's defocus_angle. */
static int parse_lens(rt_json_ctx *c, const cJSON *cam, const char *w, rt_camera_desc *d)
{
    const cJSON *aperture = cJSON_GetObjectItemCaseSensitive(cam, "aperture");
    const cJSON *angle = cJSON_GetObjectItemCaseSensitive(cam, "defocus_angle");
    d->aperture = 0.0;
    if (aperture && angle)
        return rt_json_fail(c, RT_EFORMAT, w, "give the lens as aperture or as defocus_angle, not both");
    int st = rt_json_opt_number(c, cam, w, "aperture", 0.0, RT_JSON_MAX_COORD, RT_JSON_CLOSED, &d->aperture);
    if (!st && angle) {
        /* a cone of this angle with its apex at the focus plane has a base
         * of diameter 2 focus_dist tan(angle / 2) */
        char at[240];
        rt_json_join(at, sizeof at, w, "defocus_angle");
        double deg;
        st = rt_json_number(c, angle, at, 0.0, 180.0, RT_JSON_OPEN_HI, &deg);
        if (!st)
            d->aperture = 2.0 * d->focus_dist * tan(deg * PI / 360.0);
    }
    return st;
}

/* A view (the camera's, or a keyframe's: w names it) of obj, whose keys
 * were checked: lookfrom and lookat, then the optional fields. */
static int parse_view(rt_json_ctx *c, const cJSON *cam, const char *w, rt_camera_desc *d)
{
    int st = rt_json_point(c, cam, w, "lookfrom", &d->lookfrom);
    if (!st)
        st = rt_json_point(c, cam, w, "lookat", &d->lookat);
    if (!st)
        st = rt_json_member_vec3(c, cam, w, "vup", 0, -RT_JSON_MAX_COORD, RT_JSON_MAX_COORD, &d->vup);
    if (!st)
        st = rt_json_opt_number(c, cam, w, "vfov", 0.0, 180.0, RT_JSON_OPEN_LO | RT_JSON_OPEN_HI, &d->vfov_deg);
    if (st)
        return st;
    char at[240];
    d->focus_dist = rt_v3_len(rt_v3_sub(d->lookfrom, d->lookat));
    rt_json_join(at, sizeof at, w, "lookat");
    if (d->focus_dist == 0.0)
        return rt_json_fail(c, RT_EFORMAT, at, "equals %s.lookfrom (no view direction)", w);
    st = rt_json_opt_number(c, cam, w, "focus_dist", 0.0, RT_JSON_MAX_COORD, RT_JSON_OPEN_LO, &d->focus_dist);
    return st ? st : parse_lens(c, cam, w, d);
}

/* rt_camera_init's check of a view (the camera's or a key's). */
static int check_view(rt_json_ctx *c, const char *w, const rt_camera_desc *d)
{
    char at[240];
    rt_json_join(at, sizeof at, w, "vup");
    rt_camera probe;
    if (rt_camera_init(&probe, d, 1.0) != RT_OK)
        return rt_json_fail(c, RT_EFORMAT, at, "zero or parallel to the view direction (lookat - lookfrom)");
    return RT_OK;
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
        st = parse_view(c, cam, w, d);
    const cJSON *px = cJSON_GetObjectItemCaseSensitive(cam, "pixels");
    if (!st && px) {
        if (cJSON_IsString(px) && !strcmp(px->valuestring, "book1"))
            d->pixels = RT_PIXELS_SEED;
        else if (cJSON_IsString(px) && !strcmp(px->valuestring, "book2"))
            d->pixels = RT_PIXELS_BOOK2;
        else
            return rt_json_fail(c, RT_EFORMAT, "camera.pixels", "expected \"book1\" or \"book2\"");
    }
    return st ? st : check_view(c, w, d);
}

/* One of "camera_keys": a frame and a view as the camera's (anim.h). */
static int parse_key(rt_json_ctx *c, const cJSON *e, const char *w, const rt_xform *x, int depth, rt_scene *s)
{
    static const char *const keys[] = {"frame",         "lookfrom",   "lookat", "vup", "vfov", "aperture",
                                       "defocus_angle", "focus_dist", NULL};
    (void)x;
    (void)depth;
    char at[240];
    rt_json_join(at, sizeof at, w, "frame");
    if (s->keys.n >= RT_SCENE_MAX_KEYS)
        return rt_json_fail(c, RT_EFORMAT, w, "more than %u camera keys", RT_SCENE_MAX_KEYS);
    rt_camera_key k;
    rt_camera_desc d = s->camera;
    d.vup = rt_v3(0, 1, 0);
    d.vfov_deg = 90.0;
    int st = rt_json_need_object(c, e, w);
    if (!st)
        st = rt_json_check_keys(c, e, w, keys);
    if (!st)
        st = rt_json_req_number(c, e, w, "frame", 0.0, 4294967295.0, RT_JSON_CLOSED, &k.frame);
    if (!st && s->keys.n && !(k.frame > s->keys.items[s->keys.n - 1].frame))
        st = rt_json_fail(c, RT_EFORMAT, at, "%.17g is not after the previous key's frame (keys in increasing order, "
                          "each frame once)", k.frame);
    if (!st)
        st = parse_view(c, e, w, &d);
    if (!st)
        st = check_view(c, w, &d);
    if (st)
        return st;
    k.lookfrom = d.lookfrom;
    k.lookat = d.lookat;
    k.vup = d.vup;
    k.vfov_deg = d.vfov_deg;
    k.aperture = d.aperture;
    k.focus_dist = d.focus_dist;
    return rt_json_add_status(c, rt_anim_add_key(s, &k), w);
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
    static const char *const keys1[] = {"version", "camera", "camera_keys", "background", "materials", "spheres",
                                        NULL};
    static const char *const keys2[] = {"version",   "camera",  "camera_keys",    "background", "noise_seed",
                                        "textures",  "materials", "frames",       "groups",     "spheres",
                                        "moving_spheres", "quads", "boxes",       "media",      "instances",
                                        NULL};
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
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(root, "camera_keys");
    if (!st && item)
        st = rt_json_each(c, item, "", "camera_keys", parse_key, NULL, 0, s);
    item = cJSON_GetObjectItemCaseSensitive(root, "background");
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
