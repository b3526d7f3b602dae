/* scene_json.c - loading scene files with cJSON (strict: unknown or
 * duplicate fields, wrong types and out-of-range values are refused with
 * the field's path), and writing them back with round-trip exact numbers. */
#include "scene_json.h"
#include "io_internal.h"

#include "array.h"

#include <cJSON.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "camera.h"
#include "fileio.h"
#include "status.h"

/* Coordinates and radii beyond this would overflow the squares taken by the
 * intersection and the BVH's boxes. */
#define MAX_COORD 1e12
#define MAX_SKY 1000.0
#define MAX_IOR 100.0

typedef struct ctx {
    const char *name;
    char *err;
    size_t errlen;
} ctx;

static int fail(ctx *c, int status, const char *where, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static int fail(ctx *c, int status, const char *where, const char *fmt, ...)
{
    char msg[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (c->errlen)
        snprintf(c->err, c->errlen, "%s: %s%s%s", c->name, where, *where ? ": " : "", msg);
    return status;
}

/* A key from the file, fit to quote in a one-line message. */
static void quote_key(const char *key, char *out, size_t n)
{
    size_t j = 0;
    for (size_t i = 0; key[i] && j + 4 < n; i++) {
        if (i == 40) {
            out[j++] = '.';
            out[j++] = '.';
            out[j++] = '.';
            break;
        }
        unsigned char ch = (unsigned char)key[i];
        out[j++] = ch >= 0x20 && ch < 0x7f ? (char)ch : '?';
    }
    out[j] = 0;
}

static void join(char *out, size_t n, const char *where, const char *key)
{
    snprintf(out, n, "%s%s%s", where, *where ? "." : "", key);
}

/* Every key of obj must be one of allowed (NULL-terminated) and appear once. */
static int check_keys(ctx *c, const cJSON *obj, const char *where, const char *const *allowed)
{
    const cJSON *item;
    cJSON_ArrayForEach(item, obj)
    {
        char q[48], at[160];
        quote_key(item->string ? item->string : "", q, sizeof q);
        join(at, sizeof at, where, q);
        int known = 0;
        for (const char *const *a = allowed; *a; a++)
            known |= !strcmp(item->string, *a);
        if (!known) {
            char list[160] = "";
            for (const char *const *a = allowed; *a; a++)
                snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", a == allowed ? "" : ", ", *a);
            return fail(c, RT_EFORMAT, at, "unknown field (expected one of: %s)", list);
        }
        for (const cJSON *prev = obj->child; prev != item; prev = prev->next)
            if (!strcmp(prev->string, item->string))
                return fail(c, RT_EFORMAT, at, "duplicate field");
    }
    return RT_OK;
}

static int need_object(ctx *c, const cJSON *item, const char *where)
{
    if (!item)
        return fail(c, RT_EFORMAT, where, "missing");
    return cJSON_IsObject(item) ? RT_OK : fail(c, RT_EFORMAT, where, "expected an object");
}

/* A finite number in [lo, hi]; OPEN_LO / OPEN_HI leave an end out of the
 * range. A NULL item is "missing". */
enum { CLOSED = 0, OPEN_LO = 1, OPEN_HI = 2 };
static int get_number_in(ctx *c, const cJSON *item, const char *where, double lo, double hi, int open,
                         double *out)
{
    if (!item)
        return fail(c, RT_EFORMAT, where, "missing");
    if (!cJSON_IsNumber(item))
        return fail(c, RT_EFORMAT, where, "expected a number");
    double v = item->valuedouble;
    if (!isfinite(v))
        return fail(c, RT_EFORMAT, where, "expected a finite number");
    if (!(open & OPEN_LO ? v > lo : v >= lo) || !(open & OPEN_HI ? v < hi : v <= hi))
        return fail(c, RT_EFORMAT, where, "%.17g is out of range %c%g, %g%c", v, open & OPEN_LO ? '(' : '[', lo, hi,
                    open & OPEN_HI ? ')' : ']');
    *out = v;
    return RT_OK;
}

static int get_number(ctx *c, const cJSON *item, const char *where, double lo, double hi, double *out)
{
    return get_number_in(c, item, where, lo, hi, CLOSED, out);
}

static int get_vec3(ctx *c, const cJSON *item, const char *where, double lo, double hi, rt_vec3 *out)
{
    if (!item)
        return fail(c, RT_EFORMAT, where, "missing");
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 3)
        return fail(c, RT_EFORMAT, where, "expected an array of 3 numbers");
    double v[3];
    int i = 0;
    const cJSON *e;
    cJSON_ArrayForEach(e, item)
    {
        char at[200];
        snprintf(at, sizeof at, "%s[%d]", where, i);
        int st = get_number(c, e, at, lo, hi, &v[i]);
        if (st)
            return st;
        i++;
    }
    *out = rt_v3(v[0], v[1], v[2]);
    return RT_OK;
}

/* Optional member: the default stays in *out when absent. */
static int opt_number(ctx *c, const cJSON *obj, const char *where, const char *key, double lo, double hi,
                      int open, double *out)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
    char at[200];
    join(at, sizeof at, where, key);
    return item ? get_number_in(c, item, at, lo, hi, open, out) : RT_OK;
}

static int member_vec3(ctx *c, const cJSON *obj, const char *where, const char *key, int required, double lo,
                       double hi, rt_vec3 *out)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
    char at[200];
    join(at, sizeof at, where, key);
    return item || required ? get_vec3(c, item, at, lo, hi, out) : RT_OK;
}

static int parse_camera(ctx *c, const cJSON *cam, rt_camera_desc *d)
{
    static const char *const keys[] = {"lookfrom", "lookat",     "vup", "vfov", "aperture", "defocus_angle",
                                       "focus_dist", NULL};
    const char *w = "camera";
    int st = need_object(c, cam, w);
    if (!st)
        st = check_keys(c, cam, w, keys);
    if (!st)
        st = member_vec3(c, cam, w, "lookfrom", 1, -MAX_COORD, MAX_COORD, &d->lookfrom);
    if (!st)
        st = member_vec3(c, cam, w, "lookat", 1, -MAX_COORD, MAX_COORD, &d->lookat);
    d->vup = rt_v3(0, 1, 0);
    if (!st)
        st = member_vec3(c, cam, w, "vup", 0, -MAX_COORD, MAX_COORD, &d->vup);
    d->vfov_deg = 90.0;
    if (!st)
        st = opt_number(c, cam, w, "vfov", 0.0, 180.0, OPEN_LO | OPEN_HI, &d->vfov_deg);
    if (st)
        return st;
    d->focus_dist = rt_v3_len(rt_v3_sub(d->lookfrom, d->lookat));
    if (d->focus_dist == 0.0)
        return fail(c, RT_EFORMAT, "camera.lookat", "equals camera.lookfrom (no view direction)");
    st = opt_number(c, cam, w, "focus_dist", 0.0, MAX_COORD, OPEN_LO, &d->focus_dist);
    const cJSON *aperture = cJSON_GetObjectItemCaseSensitive(cam, "aperture");
    const cJSON *angle = cJSON_GetObjectItemCaseSensitive(cam, "defocus_angle");
    d->aperture = 0.0;
    if (!st && aperture && angle)
        return fail(c, RT_EFORMAT, w, "give the lens as aperture or as defocus_angle, not both");
    if (!st)
        st = opt_number(c, cam, w, "aperture", 0.0, MAX_COORD, CLOSED, &d->aperture);
    if (!st && angle) {
        /* Book v4's lens: a cone of this angle with its apex at the focus
         * plane has a base of diameter 2 focus_dist tan(angle / 2). */
        double deg;
        st = get_number_in(c, angle, "camera.defocus_angle", 0.0, 180.0, OPEN_HI, &deg);
        if (!st)
            d->aperture = 2.0 * d->focus_dist * tan(deg * 3.14159265358979323846 / 360.0);
    }
    rt_camera probe;
    if (!st && rt_camera_init(&probe, d, 1.0) != RT_OK)
        return fail(c, RT_EFORMAT, "camera.vup", "zero or parallel to the view direction (lookat - lookfrom)");
    return st;
}

static int parse_background(ctx *c, const cJSON *bg, rt_scene *s)
{
    static const char *const keys[] = {"bottom", "top", NULL};
    const char *w = "background";
    int st = need_object(c, bg, w);
    if (!st)
        st = check_keys(c, bg, w, keys);
    if (!st)
        st = member_vec3(c, bg, w, "bottom", 0, 0.0, MAX_SKY, &s->sky_bottom);
    if (!st)
        st = member_vec3(c, bg, w, "top", 0, 0.0, MAX_SKY, &s->sky_top);
    return st;
}

static int parse_material(ctx *c, const cJSON *obj, const char *w, rt_material *m)
{
    static const char *const lam_keys[] = {"type", "albedo", NULL};
    static const char *const metal_keys[] = {"type", "albedo", "fuzz", NULL};
    static const char *const glass_keys[] = {"type", "ior", NULL};
    int st = need_object(c, obj, w);
    if (st)
        return st;
    char at[200];
    join(at, sizeof at, w, "type");
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(obj, "type");
    if (!type)
        return fail(c, RT_EFORMAT, at, "missing");
    if (!cJSON_IsString(type))
        return fail(c, RT_EFORMAT, at, "expected a string");
    rt_vec3 albedo = rt_v3(0, 0, 0);
    if (!strcmp(type->valuestring, "lambertian")) {
        st = check_keys(c, obj, w, lam_keys);
        if (!st)
            st = member_vec3(c, obj, w, "albedo", 1, 0.0, 1.0, &albedo);
        *m = rt_scene_lambertian(albedo);
    } else if (!strcmp(type->valuestring, "metal")) {
        double fuzz = 0.0;
        st = check_keys(c, obj, w, metal_keys);
        if (!st)
            st = member_vec3(c, obj, w, "albedo", 1, 0.0, 1.0, &albedo);
        if (!st)
            st = opt_number(c, obj, w, "fuzz", 0.0, 1.0, CLOSED, &fuzz);
        *m = rt_scene_metal(albedo, fuzz);
    } else if (!strcmp(type->valuestring, "dielectric")) {
        double ior = 0.0;
        st = check_keys(c, obj, w, glass_keys);
        if (!st) {
            join(at, sizeof at, w, "ior");
            const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, "ior");
            st = get_number_in(c, item, at, 0.0, MAX_IOR, OPEN_LO, &ior);
        }
        *m = rt_scene_dielectric(ior);
    } else {
        char q[48];
        quote_key(type->valuestring, q, sizeof q);
        return fail(c, RT_EFORMAT, at, "'%s' is not one of lambertian, metal, dielectric", q);
    }
    return st;
}

static int add_status(ctx *c, int st, const char *where)
{
    if (st == RT_EOVERFLOW)
        return fail(c, st, where, "more than %u entries", RT_SCENE_MAX_SPHERES);
    return st == RT_ENOMEM ? fail(c, st, where, "out of memory") : st;
}

/* One entry of the materials table. */
static int parse_table_material(ctx *c, const cJSON *e, const char *w, uint32_t n_table, rt_scene *s)
{
    (void)n_table;
    rt_material m;
    int st = parse_material(c, e, w, &m);
    return st ? st : add_status(c, rt_scene_add_material(s, &m, NULL), "materials");
}

typedef int (*element_fn)(ctx *c, const cJSON *e, const char *where, uint32_t n_table, rt_scene *s);

/* Calls fn for each element of the array arr (named key), in order. */
static int each_element(ctx *c, const cJSON *arr, const char *key, element_fn fn, rt_scene *s)
{
    if (!arr)
        return fail(c, RT_EFORMAT, key, "missing");
    if (!cJSON_IsArray(arr))
        return fail(c, RT_EFORMAT, key, "expected an array");
    const uint32_t n_table = s->n_materials; /* spheres may refer to these */
    const cJSON *e;
    uint32_t i = 0;
    cJSON_ArrayForEach(e, arr)
    {
        char w[64];
        snprintf(w, sizeof w, "%s[%u]", key, i++);
        int st = fn(c, e, w, n_table, s);
        if (st)
            return st;
    }
    return RT_OK;
}

static int parse_sphere(ctx *c, const cJSON *obj, const char *w, uint32_t n_table, rt_scene *s)
{
    static const char *const keys[] = {"center", "radius", "material", NULL};
    int st = need_object(c, obj, w);
    if (!st)
        st = check_keys(c, obj, w, keys);
    rt_vec3 center;
    double radius;
    if (!st)
        st = member_vec3(c, obj, w, "center", 1, -MAX_COORD, MAX_COORD, &center);
    char at[200];
    join(at, sizeof at, w, "radius");
    if (!st)
        st = get_number(c, cJSON_GetObjectItemCaseSensitive(obj, "radius"), at, -MAX_COORD, MAX_COORD, &radius);
    if (!st && radius == 0.0)
        st = fail(c, RT_EFORMAT, at, "must not be 0 (a negative radius makes a hollow sphere)");
    if (st)
        return st;
    join(at, sizeof at, w, "material");
    const cJSON *mat = cJSON_GetObjectItemCaseSensitive(obj, "material");
    uint32_t index;
    if (!mat)
        return fail(c, RT_EFORMAT, at, "missing");
    if (cJSON_IsNumber(mat)) {
        double v = mat->valuedouble;
        if (!(v >= 0 && v < (double)n_table && v == floor(v))) {
            if (n_table == 0)
                return fail(c, RT_EFORMAT, at, "%.17g is not an index into materials (there are none)", v);
            return fail(c, RT_EFORMAT, at, "%.17g is not an index into materials (0 to %u)", v, n_table - 1);
        }
        index = (uint32_t)v;
    } else if (cJSON_IsObject(mat)) {
        rt_material m;
        st = parse_material(c, mat, at, &m);
        if (!st)
            st = add_status(c, rt_scene_add_material(s, &m, &index), "materials");
        if (st)
            return st;
    } else {
        return fail(c, RT_EFORMAT, at, "expected an index into materials or a material object");
    }
    return add_status(c, rt_scene_add_sphere(s, center, radius, index), "spheres");
}

static int parse_root(ctx *c, const cJSON *root, rt_scene *s)
{
    static const char *const keys[] = {"version", "camera", "background", "materials", "spheres", NULL};
    if (!cJSON_IsObject(root))
        return fail(c, RT_EFORMAT, "", "expected a JSON object at the top level");
    int st = check_keys(c, root, "", keys);
    const cJSON *version = cJSON_GetObjectItemCaseSensitive(root, "version");
    if (!st && version && !(cJSON_IsNumber(version) && version->valuedouble == RT_SCENE_JSON_VERSION))
        st = fail(c, RT_EFORMAT, "version", "this program reads version %d only", RT_SCENE_JSON_VERSION);
    if (!st)
        st = parse_camera(c, cJSON_GetObjectItemCaseSensitive(root, "camera"), &s->camera);
    const cJSON *bg = cJSON_GetObjectItemCaseSensitive(root, "background");
    if (!st && bg)
        st = parse_background(c, bg, s);
    const cJSON *mats = cJSON_GetObjectItemCaseSensitive(root, "materials");
    if (!st && mats)
        st = each_element(c, mats, "materials", parse_table_material, s);
    if (!st)
        st = each_element(c, cJSON_GetObjectItemCaseSensitive(root, "spheres"), "spheres", parse_sphere, s);
    return st;
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

int rt_scene_json_parse(rt_scene *s, const char *text, size_t len, const char *name, char *err, size_t errlen)
{
    ctx c = {name, err, errlen};
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
        int st = fail(&c, RT_EFORMAT, where, !len ? "empty file" : root ? "unexpected text after the JSON value"
                                                                         : "invalid JSON");
        cJSON_Delete(root);
        return st;
    }
    int st = parse_root(&c, root, s);
    cJSON_Delete(root);
    if (st)
        rt_scene_free(s);
    return st;
}

int rt_scene_json_load(rt_scene *s, const char *path, char *err, size_t errlen)
{
    ctx c = {path, err, errlen};
    rt_scene_init(s); /* valid (empty) also when the file cannot be read */
    char *buf;
    size_t n;
    int st = rt_file_read_all(path, RT_SCENE_JSON_MAX_BYTES, &buf, &n);
    if (st == RT_EOVERFLOW)
        return fail(&c, st, "", "larger than %u MiB", RT_SCENE_JSON_MAX_BYTES >> 20);
    if (st == RT_EIO)
        return fail(&c, st, "", "cannot read: %s", strerror(errno));
    if (st)
        return fail(&c, st, "", "%s", rt_status_str(st));
    st = rt_scene_json_parse(s, buf, n, path, err, errlen);
    free(buf);
    return st;
}

/* ---- writing ---------------------------------------------------------- */

typedef struct sbuf {
    char *p;
    size_t len, cap;
    int oom;
} sbuf;

static void put(sbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void put(sbuf *b, const char *fmt, ...)
{
    if (b->oom)
        return;
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int n = vsnprintf(b->p + b->len, b->cap - b->len, fmt, ap);
        va_end(ap);
        if (n < 0) {
            b->oom = 1;
            return;
        }
        if ((size_t)n < b->cap - b->len) {
            b->len += (size_t)n;
            return;
        }
        if (rt_array_reserve((void **)&b->p, &b->cap, b->len + (size_t)n + 1, 1) != RT_OK) {
            b->oom = 1;
            return;
        }
    }
}

/* prefix, then d with the fewest "%.*g" digits that read back to exactly
 * d: as exact as "%.17g" but 0.1 stays "0.1", so dumps remain readable
 * and editable. Whole numbers are written whole (20, not 2e+01). */
static void put_num(sbuf *b, const char *prefix, double d)
{
    char tmp[40];
    if (d == floor(d) && fabs(d) < 1e15) {
        snprintf(tmp, sizeof tmp, "%.0f", d);
    } else {
        /* "%.15g" already drops trailing zeros, so it is the shortest form
         * whenever one of 15 digits or fewer exists; only subnormals need the
         * search from 1 digit up. */
        int first = fabs(d) < DBL_MIN ? 1 : 15;
        for (int prec = first; prec <= 17; prec++) {
            snprintf(tmp, sizeof tmp, "%.*g", prec, d);
            double back = strtod(tmp, NULL);
            if (memcmp(&back, &d, sizeof d) == 0)
                break;
        }
    }
    put(b, "%s%s", prefix, tmp);
}

static void put_vec(sbuf *b, const char *prefix, rt_vec3 v)
{
    put_num(b, prefix, v.x);
    put_num(b, ", ", v.y);
    put_num(b, ", ", v.z);
    put(b, "]");
}

int rt_scene_json_format(const rt_scene *s, char **text, size_t *len)
{
    if (rt_scene_is_book2(s)) /* the file format does not hold book 2's content yet */
        return RT_EUNSUPPORTED;
    sbuf b = {.p = malloc(4096), .cap = 4096};
    if (!b.p)
        return RT_ENOMEM;
    const rt_camera_desc *c = &s->camera;
    put(&b, "{\n  \"version\": %d,\n  \"camera\": {\n", RT_SCENE_JSON_VERSION);
    put_vec(&b, "    \"lookfrom\": [", c->lookfrom);
    put_vec(&b, ",\n    \"lookat\": [", c->lookat);
    put_vec(&b, ",\n    \"vup\": [", c->vup);
    put_num(&b, ",\n    \"vfov\": ", c->vfov_deg);
    put_num(&b, ",\n    \"aperture\": ", c->aperture);
    put_num(&b, ",\n    \"focus_dist\": ", c->focus_dist);
    put_vec(&b, "\n  },\n  \"background\": {\"bottom\": [", s->sky_bottom);
    put_vec(&b, ", \"top\": [", s->sky_top);
    put(&b, "},\n  \"materials\": [");
    for (uint32_t i = 0; i < s->n_materials; i++) {
        const rt_material *m = &s->materials[i];
        put(&b, "%s\n    {\"type\": ", i ? "," : "");
        if (m->kind == RT_MAT_DIELECTRIC) {
            put_num(&b, "\"dielectric\", \"ior\": ", m->ior);
        } else {
            put_vec(&b, m->kind == RT_MAT_METAL ? "\"metal\", \"albedo\": [" : "\"lambertian\", \"albedo\": [",
                    m->albedo);
            if (m->kind == RT_MAT_METAL)
                put_num(&b, ", \"fuzz\": ", m->fuzz);
        }
        put(&b, "}");
    }
    put(&b, "%s],\n  \"spheres\": [", s->n_materials ? "\n  " : "");
    for (uint32_t i = 0; i < s->n_spheres; i++) {
        const rt_sphere *sp = &s->spheres[i];
        put_vec(&b, i ? ",\n    {\"center\": [" : "\n    {\"center\": [", sp->center);
        put_num(&b, ", \"radius\": ", sp->radius);
        put(&b, ", \"material\": %u}", sp->material);
    }
    put(&b, "%s]\n}\n", s->n_spheres ? "\n  " : "");
    if (b.oom) {
        free(b.p);
        return RT_ENOMEM;
    }
    *text = b.p;
    *len = b.len;
    return RT_OK;
}

int rt_scene_json_dump(const rt_scene *s, const char *path)
{
    char *text;
    size_t len;
    int st = rt_scene_json_format(s, &text, &len);
    if (st)
        return st;
    rt_atomic_file f;
    st = rt_atomic_open(&f, path);
    if (!st) {
        /* a short write leaves ferror set: commit reports it (full disk
         * included) and removes the temporary file */
        (void)fwrite(text, 1, len, f.fp);
        st = rt_atomic_commit(&f);
    }
    free(text);
    return st;
}
