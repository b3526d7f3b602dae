/* scene_bytes.c - the scene's byte format, which rank 0 broadcasts:
 * version 1 for book 1's scenes (unchanged, so their bytes and hashes
 * are), version 2 when a scene has anything of book 2's, version 3 when
 * its camera has keyframes (version 2's bytes, then the keys and their
 * count just before the checksum). Every field is checked on load,
 * through the same add functions the builders use. */
#include "scene.h"
#include "core_internal.h"

#include "anim.h"

#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "hash.h"
#include "status.h"

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
static uint64_t get_u64(reader *r) { return get_bytes(r, 8); }
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

static void put_quad(writer *w, const rt_quad *q)
{
    put_v3(w, q->q);
    put_v3(w, q->u);
    put_v3(w, q->v);
    put_u32(w, q->material);
}
static rt_quad get_quad(reader *r)
{
    rt_quad q;
    q.q = get_v3(r);
    q.u = get_v3(r);
    q.v = get_v3(r);
    q.material = get_u32(r);
    return q;
}

#define MAT_BYTES (4 + 24 + 8 + 8)
#define MAT2_BYTES (4 + 4 + 24) /* version 2: texture, flags, emit */
#define SPHERE_BYTES (24 + 8 + 4)
#define SPHERE2_BYTES 4 /* version 2: frame */
#define HEADER_BYTES (8 + 4 + 4 + 4)
#define FIXED_BYTES (4 * 24 + 3 * 8 + 2 * 24)
/* version 2: camera pixels, background kind and colour, noise seed, 8 counts */
#define FIXED2_BYTES (4 + 4 + 24 + 8 + 7 * 4 + 8)
#define QUAD_BYTES (3 * 24 + 4)
#define MOVER_BYTES (2 * 24 + 8 + 4 + 4)
#define FRAME_BYTES (3 * 24)
#define MEDIUM_BYTES (4 + 24 + 8 + 4 + 4 + 8 + 4)
#define TEXTURE_BYTES (4 + 24 + 8 + 4 + 4 + 4 + 4)
#define IMAGE_BYTES (4 + 4)
#define KEY_BYTES (8 + 3 * 24 + 3 * 8) /* version 3: frame, lookfrom, lookat, vup, vfov, aperture, focus_dist */

typedef struct counts2 {
    uint32_t quads, movers, frames, media, hull, textures, images;
    uint64_t texels;
    uint32_t keys; /* version 3 */
} counts2;

/* The bytes of a scene of nm materials and ns spheres (and, in version 2,
 * the lists of k) in format version `version`, checksum included. */
static uint64_t scene_bytes(uint32_t nm, uint32_t ns, const counts2 *k, uint32_t version)
{
    uint64_t n = HEADER_BYTES + FIXED_BYTES + (uint64_t)nm * MAT_BYTES + (uint64_t)ns * SPHERE_BYTES + 8;
    if (version == 3)
        n += 4 + (uint64_t)k->keys * KEY_BYTES;
    if (version >= 2)
        n += FIXED2_BYTES + (uint64_t)nm * MAT2_BYTES + (uint64_t)ns * SPHERE2_BYTES + (uint64_t)k->quads * QUAD_BYTES +
             (uint64_t)k->movers * MOVER_BYTES + (uint64_t)k->frames * FRAME_BYTES +
             (uint64_t)k->media * MEDIUM_BYTES + (uint64_t)k->hull * QUAD_BYTES +
             (uint64_t)k->textures * TEXTURE_BYTES + (uint64_t)k->images * IMAGE_BYTES + k->texels;
    return n;
}

static counts2 counts_of(const rt_scene *s)
{
    counts2 k = {.quads = s->shapes.quads.n,
                 .movers = s->shapes.movers.n,
                 .frames = s->shapes.frames.n,
                 .media = s->media.media.n,
                 .hull = s->media.hull.n,
                 .textures = s->tex.textures.n,
                 .images = s->tex.images.n,
                 .texels = s->tex.n_texels,
                 .keys = s->keys.n};
    return k;
}

/* Version 2's part after version 1's: book 2's lists, images first. */
static void put_book2(writer *w, const rt_scene *s)
{
    put_u32(w, s->camera.pixels);
    put_u32(w, s->background_kind);
    put_v3(w, s->background);
    put_u64(w, s->tex.noise_seed);
    put_u32(w, s->shapes.quads.n);
    put_u32(w, s->shapes.movers.n);
    put_u32(w, s->shapes.frames.n);
    put_u32(w, s->media.media.n);
    put_u32(w, s->media.hull.n);
    put_u32(w, s->tex.textures.n);
    put_u32(w, s->tex.images.n);
    put_u64(w, s->tex.n_texels);
    for (uint32_t i = 0; i < s->n_materials; i++) {
        put_u32(w, s->materials[i].texture);
        put_u32(w, s->materials[i].flags);
        put_v3(w, s->materials[i].emit);
    }
    for (uint32_t i = 0; i < s->n_spheres; i++)
        put_u32(w, s->spheres[i].frame);
    for (uint32_t i = 0; i < s->tex.images.n; i++) {
        put_u32(w, s->tex.images.items[i].width);
        put_u32(w, s->tex.images.items[i].height);
    }
    if (s->tex.n_texels) /* no texels: texels may be NULL */
        memcpy(w->p, s->tex.texels, s->tex.n_texels);
    w->p += s->tex.n_texels;
    for (uint32_t i = 0; i < s->tex.textures.n; i++) {
        const rt_texture *t = &s->tex.textures.items[i];
        put_u32(w, t->kind);
        put_v3(w, t->color);
        put_f64(w, t->scale);
        put_u32(w, t->even);
        put_u32(w, t->odd);
        put_u32(w, t->mode);
        put_u32(w, t->image);
    }
    for (uint32_t i = 0; i < s->shapes.frames.n; i++)
        for (int k = 0; k < 3; k++)
            put_v3(w, s->shapes.frames.items[i].row[k]);
    for (uint32_t i = 0; i < s->shapes.quads.n; i++)
        put_quad(w, &s->shapes.quads.items[i]);
    for (uint32_t i = 0; i < s->shapes.movers.n; i++) {
        const rt_mover *m = &s->shapes.movers.items[i];
        put_v3(w, m->center0);
        put_v3(w, m->center1);
        put_f64(w, m->radius);
        put_u32(w, m->material);
        put_u32(w, m->frame);
    }
    for (uint32_t i = 0; i < s->media.hull.n; i++)
        put_quad(w, &s->media.hull.items[i]);
    for (uint32_t i = 0; i < s->media.media.n; i++) {
        const rt_medium *m = &s->media.media.items[i];
        put_u32(w, m->shape);
        put_v3(w, m->center);
        put_f64(w, m->radius);
        put_u32(w, m->first);
        put_u32(w, m->count);
        put_f64(w, m->density);
        put_u32(w, m->material);
    }
}

static void put_keys(writer *w, const rt_scene *s)
{
    for (uint32_t i = 0; i < s->keys.n; i++) {
        const rt_camera_key *k = &s->keys.items[i];
        put_f64(w, k->frame);
        put_v3(w, k->lookfrom);
        put_v3(w, k->lookat);
        put_v3(w, k->vup);
        put_f64(w, k->vfov_deg);
        put_f64(w, k->aperture);
        put_f64(w, k->focus_dist);
    }
    put_u32(w, s->keys.n);
}

static int get_keys(reader *r, rt_scene *s, uint32_t n)
{
    int st = RT_OK;
    for (uint32_t i = 0; i < n && !st; i++) {
        rt_camera_key k;
        k.frame = get_f64(r);
        k.lookfrom = get_v3(r);
        k.lookat = get_v3(r);
        k.vup = get_v3(r);
        k.vfov_deg = get_f64(r);
        k.aperture = get_f64(r);
        k.focus_dist = get_f64(r);
        st = rt_anim_add_key(s, &k);
    }
    (void)get_u32(r); /* the count, read before */
    return st ? RT_EFORMAT : RT_OK;
}

int rt_scene_serialize(const rt_scene *s, uint8_t **buf, size_t *len)
{
    const uint32_t version = s->keys.n ? 3u : rt_scene_is_book2(s) || s->shapes.frames.n ? 2u : 1u;
    const counts2 k = counts_of(s);
    const size_t n = (size_t)scene_bytes(s->n_materials, s->n_spheres, &k, version);
    uint8_t *b = malloc(n);
    if (!b)
        return RT_ENOMEM;
    writer w = {b};
    memcpy(w.p, MAGIC, 8);
    w.p += 8;
    put_u32(&w, version);
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
    if (version >= 2)
        put_book2(&w, s);
    if (version == 3)
        put_keys(&w, s);
    put_u64(&w, rt_hash_bytes(RT_HASH_INIT, b, n - 8));
    *buf = b;
    *len = n;
    return RT_OK;
}

static int finite3(rt_vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

/* Images, textures, frames, quads, movers, hull and media, each through its
 * add function (which checks it); RT_EFORMAT for anything bad. */
static int get_lists(reader *r, rt_scene *s, const counts2 *k)
{
    int st = RT_OK;
    uint64_t texels = 0;
    uint32_t *dims = malloc(((size_t)k->images + 1) * 2 * sizeof *dims);
    if (!dims)
        return RT_ENOMEM;
    for (uint32_t i = 0; i < k->images; i++) {
        dims[2 * i] = get_u32(r);
        dims[2 * i + 1] = get_u32(r);
        texels += (uint64_t)dims[2 * i] * dims[2 * i + 1] * 3;
    }
    if (texels != k->texels || (uint64_t)(r->end - r->p) < texels)
        st = RT_EFORMAT;
    for (uint32_t i = 0; i < k->images && !st; i++) {
        st = rt_scene_add_image(s, dims[2 * i], dims[2 * i + 1], r->p, NULL);
        r->p += (size_t)dims[2 * i] * dims[2 * i + 1] * 3;
    }
    free(dims);
    for (uint32_t i = 0; i < k->textures && !st; i++) {
        rt_texture t;
        t.kind = get_u32(r);
        t.color = get_v3(r);
        t.scale = get_f64(r);
        t.even = get_u32(r);
        t.odd = get_u32(r);
        t.mode = get_u32(r);
        t.image = get_u32(r);
        st = rt_scene_add_texture(s, &t, NULL);
    }
    for (uint32_t i = 0; i < k->frames && !st; i++) {
        rt_frame f;
        for (int j = 0; j < 3; j++)
            f.row[j] = get_v3(r);
        if (!finite3(f.row[0]) || !finite3(f.row[1]) || !finite3(f.row[2]))
            st = RT_EFORMAT;
        else if (!(st = rt_array_reserve((void **)&s->shapes.frames.items, &s->shapes.frames.cap,
                                         (size_t)s->shapes.frames.n + 1, sizeof f)))
            s->shapes.frames.items[s->shapes.frames.n++] = f;
    }
    for (uint32_t i = 0; i < k->quads && !st; i++) {
        const rt_quad q = get_quad(r);
        st = rt_scene_add_quad(s, q.q, q.u, q.v, q.material, NULL);
    }
    for (uint32_t i = 0; i < k->movers && !st; i++) {
        const rt_vec3 c0 = get_v3(r), c1 = get_v3(r);
        const double radius = get_f64(r);
        const uint32_t m = get_u32(r), frame = get_u32(r);
        st = frame > s->shapes.frames.n ? RT_EFORMAT : rt_scene_add_mover(s, c0, c1, radius, m, NULL);
        if (!st)
            s->shapes.movers.items[s->shapes.movers.n - 1].frame = frame;
    }
    return st;
}

/* The hull quads and the media. */
static int get_media(reader *r, rt_scene *s, const counts2 *k)
{
    int st = RT_OK;
    for (uint32_t i = 0; i < k->hull && !st; i++) {
        const rt_quad q = get_quad(r);
        rt_vec3 n = rt_v3_cross(q.u, q.v);
        if (!finite3(q.q) || !finite3(q.u) || !finite3(q.v) || !(rt_v3_len2(n) > 0) || q.material)
            st = RT_EFORMAT;
        else if (!(st = rt_array_reserve((void **)&s->media.hull.items, &s->media.hull.cap,
                                         (size_t)s->media.hull.n + 1, sizeof q)))
            s->media.hull.items[s->media.hull.n++] = q;
    }
    for (uint32_t i = 0; i < k->media && !st; i++) {
        rt_medium m;
        m.shape = get_u32(r);
        m.center = get_v3(r);
        m.radius = get_f64(r);
        m.first = get_u32(r);
        m.count = get_u32(r);
        m.density = get_f64(r);
        m.material = get_u32(r);
        if (m.shape == RT_MEDIUM_SPHERE) {
            st = rt_scene_add_medium_sphere(s, m.center, m.radius, m.density, m.material);
        } else if (m.shape != RT_MEDIUM_HULL || m.count < 4 || m.first > s->media.hull.n ||
                   m.count > s->media.hull.n - m.first) { /* a closed hull has 4 faces at least */
            st = RT_EFORMAT;
        } else if (!(m.density > 0) || !isfinite(m.density) || m.material >= s->n_materials ||
                   s->media.media.n >= RT_SCENE_MAX_MEDIA) {
            st = RT_EFORMAT;
        } else if (!(st = rt_array_reserve((void **)&s->media.media.items, &s->media.media.cap,
                                           (size_t)s->media.media.n + 1, sizeof m))) {
            s->media.media.items[s->media.media.n++] = m;
        }
    }
    return st;
}

/* Version 2's part: the fixed fields and the counts, then the lists. */
static int get_book2(reader *r, rt_scene *s, uint32_t nm, uint32_t ns, counts2 *k)
{
    s->camera.pixels = get_u32(r);
    s->background_kind = get_u32(r);
    s->background = get_v3(r);
    s->tex.noise_seed = get_u64(r);
    k->quads = get_u32(r);
    k->movers = get_u32(r);
    k->frames = get_u32(r);
    k->media = get_u32(r);
    k->hull = get_u32(r);
    k->textures = get_u32(r);
    k->images = get_u32(r);
    k->texels = get_u64(r);
    if (s->camera.pixels > RT_PIXELS_BOOK2 || s->background_kind > RT_BACKGROUND_COLOR || !finite3(s->background))
        return RT_EFORMAT;
    for (uint32_t i = 0; i < nm; i++) {
        s->materials[i].texture = get_u32(r);
        s->materials[i].flags = get_u32(r);
        s->materials[i].emit = get_v3(r);
    }
    for (uint32_t i = 0; i < ns; i++)
        s->spheres[i].frame = get_u32(r);
    int st = get_lists(r, s, k);
    if (!st)
        st = get_media(r, s, k);
    for (uint32_t i = 0; i < nm && !st; i++) {
        const rt_material *m = &s->materials[i];
        if (m->texture > s->tex.textures.n || m->flags > RT_MAT_TWO_SIDED || !finite3(m->emit))
            st = RT_EFORMAT;
    }
    for (uint32_t i = 0; i < ns && !st; i++)
        if (s->spheres[i].frame > s->shapes.frames.n)
            st = RT_EFORMAT;
    return st == RT_EINVAL || st == RT_EOVERFLOW ? RT_EFORMAT : st;
}

/* The checksum a serialized scene ends with (len >= 8). */
static uint64_t checksum_of(const uint8_t *buf, size_t len)
{
    uint64_t sum = 0;
    for (int i = 0; i < 8; i++)
        sum |= (uint64_t)buf[len - 8 + i] << (8 * i);
    return sum;
}

static int decode(rt_scene *s, const uint8_t *buf, size_t len, int verify)
{
    rt_scene_init(s);
    if (len < HEADER_BYTES + FIXED_BYTES + 8 || memcmp(buf, MAGIC, 8) != 0)
        return RT_EFORMAT;
    reader r = {buf + 8, buf + len, 0};
    uint32_t version = get_u32(&r);
    if (version < 1 || version > RT_SCENE_FORMAT_VERSION)
        return RT_EVERSION;
    uint32_t nm = get_u32(&r), ns = get_u32(&r);
    if (nm > RT_SCENE_MAX_SPHERES || ns > RT_SCENE_MAX_SPHERES)
        return RT_EFORMAT;
    counts2 k = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    if (version == 3) { /* the keys' count, just before the checksum */
        reader rk = {buf + len - 12, buf + len, 0};
        k.keys = get_u32(&rk);
        if (k.keys == 0 || k.keys > RT_SCENE_MAX_KEYS)
            return RT_EFORMAT;
    }
    if (version >= 2) { /* the lists' counts, to know the length before reading */
        const uint64_t off = HEADER_BYTES + FIXED_BYTES + (uint64_t)nm * MAT_BYTES + (uint64_t)ns * SPHERE_BYTES;
        if ((uint64_t)len < off + FIXED2_BYTES + 8)
            return RT_EFORMAT;
        reader rk = {buf + off + 4 + 4 + 24 + 8, buf + len, 0};
        k.quads = get_u32(&rk);
        k.movers = get_u32(&rk);
        k.frames = get_u32(&rk);
        k.media = get_u32(&rk);
        k.hull = get_u32(&rk);
        k.textures = get_u32(&rk);
        k.images = get_u32(&rk);
        k.texels = get_u64(&rk);
        const uint32_t lim = RT_SCENE_MAX_SPHERES;
        if (k.quads > lim || k.movers > lim || k.frames > lim || k.media > RT_SCENE_MAX_MEDIA || k.hull > lim ||
            k.textures > lim || k.images > lim || k.texels > (uint64_t)len)
            return RT_EFORMAT;
    }
    if ((uint64_t)len != scene_bytes(nm, ns, &k, version))
        return RT_EFORMAT;
    if (verify && checksum_of(buf, len) != rt_hash_bytes(RT_HASH_INIT, buf, len - 8))
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
        m.texture = m.flags = 0;
        m.emit = rt_v3(0, 0, 0);
        if (m.kind > (version == 1 ? RT_MAT_DIELECTRIC : RT_MAT_ISOTROPIC) || !finite3(m.albedo) ||
            !isfinite(m.fuzz) || !isfinite(m.ior))
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
    if (!st && version >= 2)
        st = get_book2(&r, s, nm, ns, &k);
    if (!st && version == 3)
        st = get_keys(&r, s, k.keys);
    if (!st && (r.bad || !finite3(c->lookfrom) || !finite3(c->lookat) || !finite3(c->vup) ||
                !(c->vfov_deg > 0 && c->vfov_deg < 180) || !(c->aperture >= 0) || !(c->focus_dist > 0)))
        st = RT_EFORMAT;
    if (st)
        rt_scene_free(s);
    return st;
}

int rt_scene_deserialize(rt_scene *s, const uint8_t *buf, size_t len) { return decode(s, buf, len, 1); }

int rt_scene_deserialize_own(rt_scene *s, const uint8_t *buf, size_t len) { return decode(s, buf, len, 0); }

uint64_t rt_scene_bytes_hash(const uint8_t *buf, size_t len)
{
    return rt_hash_bytes(checksum_of(buf, len), buf + len - 8, 8);
}

uint64_t rt_scene_hash(const rt_scene *s)
{
    uint8_t *b;
    size_t n;
    if (rt_scene_serialize(s, &b, &n))
        return 0;
    const uint64_t h = rt_scene_bytes_hash(b, n);
    free(b);
    return h;
}
