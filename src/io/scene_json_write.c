/* scene_json_write.c - writing scene files: version 1 for book 1's scenes
 * (as before), version 2 for anything else, every number with the fewest
 * digits that read back to the same bits and every list flattened (boxes
 * as their quads, instances as what they placed, a rotated sphere with
 * its frame), so that the file loads to the very scene it was written
 * from; images as paths to their files, relative to the written file. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "scene_json.h"
#include "io_internal.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "fileio.h"
#include "status.h"

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

/* Version 1's materials: lambertian, metal, dielectric. */
static void put_material1(sbuf *b, const rt_material *m)
{
    if (m->kind == RT_MAT_DIELECTRIC) {
        put_num(b, "\"dielectric\", \"ior\": ", m->ior);
        return;
    }
    put_vec(b, m->kind == RT_MAT_METAL ? "\"metal\", \"albedo\": [" : "\"lambertian\", \"albedo\": [", m->albedo);
    if (m->kind == RT_MAT_METAL)
        put_num(b, ", \"fuzz\": ", m->fuzz);
}

static void put_material(sbuf *b, const rt_material *m)
{
    static const char *const names[] = {"lambertian", "metal", "dielectric", "emitter", "isotropic"};
    if (m->kind <= RT_MAT_DIELECTRIC && !m->texture) {
        put_material1(b, m);
        return;
    }
    put(b, "\"%s\", ", names[m->kind < 5 ? m->kind : 0]);
    const char *key = m->kind == RT_MAT_EMITTER ? "emit" : "albedo";
    if (m->texture)
        put(b, "\"texture\": %u", m->texture - 1);
    else
        put_vec(b, key[0] == 'e' ? "\"emit\": [" : "\"albedo\": [", m->kind == RT_MAT_EMITTER ? m->emit : m->albedo);
    if (m->kind == RT_MAT_EMITTER)
        put(b, ", \"two_sided\": %s", m->flags & RT_MAT_TWO_SIDED ? "true" : "false");
}

static void put_texture(sbuf *b, const rt_texture *t, const char *const *image_paths)
{
    static const char *const noise[] = {"noise", "turbulence", "marble"};
    switch (t->kind) {
    case RT_TEX_SOLID:
        put_vec(b, "\"solid\", \"color\": [", t->color);
        break;
    case RT_TEX_CHECKER:
        put_num(b, "\"checker\", \"scale\": ", t->scale);
        put(b, ", \"even\": %u, \"odd\": %u", t->even, t->odd);
        break;
    case RT_TEX_NOISE:
        put(b, "\"%s\"", noise[t->mode <= RT_NOISE_MARBLE ? t->mode : 0]);
        put_num(b, ", \"scale\": ", t->scale);
        put_vec(b, ", \"color\": [", t->color);
        break;
    default: { /* a JSON string: escape quotes, backslashes and controls */
        put(b, "\"image\", \"path\": \"");
        for (const unsigned char *p = (const unsigned char *)image_paths[t->image]; *p; p++)
            put(b, *p == '"' || *p == '\\' ? "\\%c" : *p < 0x20 ? "\\u%04x" : "%c", *p);
        put(b, "\"");
    }
    }
}

static void put_quad(sbuf *b, const char *prefix, const rt_quad *q)
{
    put_vec(b, prefix, q->q);
    put_vec(b, ", \"u\": [", q->u);
    put_vec(b, ", \"v\": [", q->v);
}

/* Opens list key (n entries); each entry then starts with item(b, i). */
static void open_list(sbuf *b, const char *key, uint32_t n) { put(b, ",\n  \"%s\": [%s", key, n ? "" : "]"); }
static void item(sbuf *b, uint32_t i) { put(b, "%s\n    {", i ? "," : ""); }
static void close_list(sbuf *b, uint32_t n)
{
    if (n)
        put(b, "\n  ]");
}

static void put_spheres(sbuf *b, const rt_scene *s)
{
    open_list(b, "spheres", s->n_spheres);
    for (uint32_t i = 0; i < s->n_spheres; i++) {
        const rt_sphere *sp = &s->spheres[i];
        item(b, i);
        put_vec(b, "\"center\": [", sp->center);
        put_num(b, ", \"radius\": ", sp->radius);
        put(b, ", \"material\": %u", sp->material);
        if (sp->frame)
            put(b, ", \"frame\": %u", sp->frame - 1);
        put(b, "}");
    }
    close_list(b, s->n_spheres);
    open_list(b, "moving_spheres", s->shapes.movers.n);
    for (uint32_t i = 0; i < s->shapes.movers.n; i++) {
        const rt_mover *m = &s->shapes.movers.items[i];
        item(b, i);
        put_vec(b, "\"center0\": [", m->center0);
        put_vec(b, ", \"center1\": [", m->center1);
        put_num(b, ", \"radius\": ", m->radius);
        put(b, ", \"material\": %u", m->material);
        if (m->frame)
            put(b, ", \"frame\": %u", m->frame - 1);
        put(b, "}");
    }
    close_list(b, s->shapes.movers.n);
}

static void put_shapes(sbuf *b, const rt_scene *s)
{
    const uint32_t nq = s->shapes.quads.n, nm = s->media.media.n;
    open_list(b, "quads", nq);
    for (uint32_t i = 0; i < nq; i++) {
        item(b, i);
        put_quad(b, "\"q\": [", &s->shapes.quads.items[i]);
        put(b, ", \"material\": %u}", s->shapes.quads.items[i].material);
    }
    close_list(b, nq);
    open_list(b, "media", nm);
    for (uint32_t i = 0; i < nm; i++) {
        const rt_medium *m = &s->media.media.items[i];
        item(b, i);
        if (m->shape == RT_MEDIUM_SPHERE) {
            put_vec(b, "\"sphere\": {\"center\": [", m->center);
            put_num(b, ", \"radius\": ", m->radius);
            put(b, "}");
        } else {
            put(b, "\"hull\": [");
            for (uint32_t k = 0; k < m->count; k++)
                put_quad(b, k ? "}, {\"q\": [" : "{\"q\": [", &s->media.hull.items[m->first + k]);
            put(b, "}]");
        }
        put_num(b, ", \"density\": ", m->density);
        put(b, ", \"material\": %u}", m->material);
    }
    close_list(b, nm);
}

/* Version 2's parts before the materials: pixels, background colour,
 * noise seed, textures. */
static void put_book2_head(sbuf *b, const rt_scene *s, const char *const *image_paths)
{
    if (s->background_kind == RT_BACKGROUND_COLOR)
        put_vec(b, ", \"color\": [", s->background);
    put(b, "},\n  \"noise_seed\": ");
    if (s->tex.noise_seed <= ((uint64_t)1 << 53))
        put(b, "%llu", (unsigned long long)s->tex.noise_seed);
    else
        put(b, "\"%llu\"", (unsigned long long)s->tex.noise_seed);
    open_list(b, "textures", s->tex.textures.n);
    for (uint32_t i = 0; i < s->tex.textures.n; i++) {
        item(b, i);
        put(b, "\"type\": ");
        put_texture(b, &s->tex.textures.items[i], image_paths);
        put(b, "}");
    }
    close_list(b, s->tex.textures.n);
}

static void put_frames(sbuf *b, const rt_scene *s)
{
    open_list(b, "frames", s->shapes.frames.n);
    for (uint32_t i = 0; i < s->shapes.frames.n; i++) {
        const rt_frame *f = &s->shapes.frames.items[i];
        put_vec(b, i ? ",\n    [[" : "\n    [[", f->row[0]);
        put_vec(b, ", [", f->row[1]);
        put_vec(b, ", [", f->row[2]);
        put(b, "]");
    }
    close_list(b, s->shapes.frames.n);
}

/* The camera's keyframes (anim.h), when it has any. */
static void put_keys(sbuf *b, const rt_scene *s)
{
    if (!s->keys.n)
        return;
    put(b, "  \"camera_keys\": [");
    for (uint32_t i = 0; i < s->keys.n; i++) {
        const rt_camera_key *k = &s->keys.items[i];
        put_num(b, i ? ",\n    {\"frame\": " : "\n    {\"frame\": ", k->frame);
        put_vec(b, ", \"lookfrom\": [", k->lookfrom);
        put_vec(b, ", \"lookat\": [", k->lookat);
        put_vec(b, ", \"vup\": [", k->vup);
        put_num(b, ", \"vfov\": ", k->vfov_deg);
        put_num(b, ", \"aperture\": ", k->aperture);
        put_num(b, ", \"focus_dist\": ", k->focus_dist);
        put(b, "}");
    }
    put(b, "\n  ],\n");
}

/* Book 1's scenes as version 1 wrote them (the same text, byte for byte). */
static void put_version1(sbuf *b, const rt_scene *s)
{
    put(b, "},\n  \"materials\": [");
    for (uint32_t i = 0; i < s->n_materials; i++) {
        put(b, "%s\n    {\"type\": ", i ? "," : "");
        put_material1(b, &s->materials[i]);
        put(b, "}");
    }
    put(b, "%s],\n  \"spheres\": [", s->n_materials ? "\n  " : "");
    for (uint32_t i = 0; i < s->n_spheres; i++) {
        const rt_sphere *sp = &s->spheres[i];
        put_vec(b, i ? ",\n    {\"center\": [" : "\n    {\"center\": [", sp->center);
        put_num(b, ", \"radius\": ", sp->radius);
        put(b, ", \"material\": %u}", sp->material);
    }
    put(b, "%s]\n}\n", s->n_spheres ? "\n  " : "");
}

int rt_scene_json_format(const rt_scene *s, const char *const *image_paths, char **text, size_t *len)
{
    const int v2 = rt_scene_is_book2(s) || s->shapes.frames.n;
    if (s->tex.images.n && !image_paths)
        return RT_EUNSUPPORTED;
    sbuf b = {.p = malloc(4096), .cap = 4096};
    if (!b.p)
        return RT_ENOMEM;
    const rt_camera_desc *c = &s->camera;
    put(&b, "{\n  \"version\": %d,\n  \"camera\": {\n", v2 ? 2 : 1);
    put_vec(&b, "    \"lookfrom\": [", c->lookfrom);
    put_vec(&b, ",\n    \"lookat\": [", c->lookat);
    put_vec(&b, ",\n    \"vup\": [", c->vup);
    put_num(&b, ",\n    \"vfov\": ", c->vfov_deg);
    put_num(&b, ",\n    \"aperture\": ", c->aperture);
    put_num(&b, ",\n    \"focus_dist\": ", c->focus_dist);
    if (v2)
        put(&b, ",\n    \"pixels\": \"%s\"", c->pixels == RT_PIXELS_BOOK2 ? "book2" : "book1");
    put(&b, "\n  },\n");
    put_keys(&b, s);
    put_vec(&b, "  \"background\": {\"bottom\": [", s->sky_bottom);
    put_vec(&b, ", \"top\": [", s->sky_top);
    if (!v2) {
        put_version1(&b, s);
    } else {
        put_book2_head(&b, s, image_paths);
        open_list(&b, "materials", s->n_materials);
        for (uint32_t i = 0; i < s->n_materials; i++) {
            item(&b, i);
            put(&b, "\"type\": ");
            put_material(&b, &s->materials[i]);
            put(&b, "}");
        }
        close_list(&b, s->n_materials);
        put_frames(&b, s);
        put_spheres(&b, s);
        put_shapes(&b, s);
        put(&b, "\n}\n");
    }
    if (b.oom) {
        free(b.p);
        return RT_ENOMEM;
    }
    *text = b.p;
    *len = b.len;
    return RT_OK;
}

/* The path from directory `from` to file `to`, both absolute and
 * canonical (realpath), into out: "../" for each of from's directories
 * below the part they share. */
static void relative(const char *from, const char *to, char *out, size_t n)
{
    char f[PATH_MAX + 1];
    snprintf(f, sizeof f, "%s%s", from, strcmp(from, "/") ? "/" : "");
    size_t common = 0;
    for (size_t i = 0; f[i] && f[i] == to[i]; i++)
        if (f[i] == '/')
            common = i + 1;
    out[0] = 0;
    for (const char *p = f + common; *p; p++)
        if (*p == '/')
            snprintf(out + strlen(out), n - strlen(out), "../");
    snprintf(out + strlen(out), n - strlen(out), "%s", to + common);
}

/* Each image's path relative to the directory of the file at path. */
static int image_paths_for(const rt_scene_files *files, const char *path, char ***out)
{
    char dir[PATH_MAX], real[PATH_MAX];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash)
        slash[slash == dir] = 0;
    else
        snprintf(dir, sizeof dir, ".");
    char *canon = realpath(dir, NULL);
    char **p = calloc(files->n + 1, sizeof *p);
    int st = canon && p ? RT_OK : RT_EIO;
    for (uint32_t i = 0; i < files->n && !st; i++) {
        char rel[PATH_MAX];
        if (!realpath(files->images[i], real))
            st = RT_EIO;
        else
            relative(canon, real, rel, sizeof rel);
        if (!st && !(p[i] = malloc(strlen(rel) + 1)))
            st = RT_ENOMEM;
        if (!st)
            strcpy(p[i], rel);
    }
    free(canon);
    *out = p;
    return st;
}

int rt_scene_json_dump(const rt_scene *s, const rt_scene_files *files, const char *path)
{
    char **paths = NULL;
    int st = files && files->n >= s->tex.images.n && s->tex.images.n ? image_paths_for(files, path, &paths) : RT_OK;
    char *text = NULL;
    size_t len;
    if (!st)
        st = rt_scene_json_format(s, (const char *const *)paths, &text, &len);
    for (uint32_t i = 0; paths && i < files->n; i++)
        free(paths[i]);
    free(paths);
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
