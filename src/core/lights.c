/* lights.c - the light list and its sampling (lights.h). Only +,-,*,/ and
 * sqrt on the sampling path, and sample.h's turn-based cosine and sine:
 * the same directions on every machine. */
#include "lights.h"

#include <stdlib.h>

#include "sample.h"
#include "status.h"
#include "warp.h"
#include "world.h"

#define PI 3.14159265358979323846

typedef struct light {
    uint64_t key;         /* kind << 32 | index: the list is sorted by it */
    rt_vec3 a, b, c;      /* quad: q, u, v; sphere: centre at times 0 and 1 (a, b), radius c.x */
    rt_vec3 n;            /* quad: unit normal */
    double area;          /* quad */
    double prob;          /* of being chosen */
    double emit;          /* luminance of its emission */
    uint32_t material;
    int one_sided;        /* quad: emits from its front face only (the side n points to) */
    rt_vec3 bc;           /* its centre (a moving sphere's halfway) */
} light;

struct rt_lights {
    light *items;
    double *cdf; /* cdf[i]: the probability of choosing a light before i + 1 */
    uint32_t n;
    light *targets; /* the glass spheres a diffuse vertex aims at, each with prob 1 / nt */
    uint32_t nt;
};

static double luminance(rt_vec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

/* The luminance of an emitter's emission: a textured emitter counts as
 * white. 0 for a material that emits nothing. */
static double radiance(const rt_scene *s, uint32_t material)
{
    const rt_material *m = &s->materials[material];
    if (m->kind != RT_MAT_EMITTER)
        return 0.0;
    const double lum = m->texture ? 1.0 : luminance(m->emit);
    return lum > 0.0 ? lum : 0.0;
}

/* The emitter's power per unit area, up to the common factor pi. */
static double exitance(const rt_scene *s, uint32_t material)
{
    return (s->materials[material].flags & RT_MAT_TWO_SIDED ? 2.0 : 1.0) * radiance(s, material);
}

static light sphere_light(uint32_t kind, uint32_t index, rt_vec3 c0, rt_vec3 c1, double radius)
{
    light L = {(uint64_t)kind << 32 | index, c0, c1, rt_v3(fabs(radius), 0, 0), rt_v3(0, 0, 0), 0, 0, 0, 0, 0,
               {0, 0, 0}};
    L.area = 4.0 * PI * radius * radius;
    return L;
}

static light quad_light(uint32_t index, const rt_quad *q)
{
    const rt_vec3 n = rt_v3_cross(q->u, q->v);
    light L = {(uint64_t)RT_SHAPE_QUAD << 32 | index, q->q, q->u, q->v, rt_v3_unit(n), rt_v3_len(n), 0, 0, 0, 0,
               {0, 0, 0}};
    return L;
}

/* Appends the light when its material emits; the power goes to prob. */
static void add(light *items, uint32_t *n, light L, const rt_scene *s, uint32_t material)
{
    const double exit = exitance(s, material);
    if (exit > 0.0 && L.area > 0.0) {
        L.prob = exit * L.area;
        L.emit = radiance(s, material);
        L.material = material;
        L.one_sided = !(s->materials[material].flags & RT_MAT_TWO_SIDED);
        L.bc = (uint32_t)(L.key >> 32) == RT_SHAPE_QUAD ? rt_v3_add(L.a, rt_v3_scale(rt_v3_add(L.b, L.c), 0.5))
                                                        : rt_v3_scale(rt_v3_add(L.a, L.b), 0.5);
        items[(*n)++] = L;
    }
}

/* l's targets: the static spheres of glass (their caustics, which only a
 * path through them finds). Returns nonzero when out of memory. */
static int targets(rt_lights *l, const rt_scene *s)
{
    uint32_t nt = 0;
    for (uint32_t i = 0; i < s->n_spheres; i++)
        nt += s->materials[s->spheres[i].material].kind == RT_MAT_DIELECTRIC;
    if (!nt)
        return 0;
    l->targets = malloc(nt * sizeof *l->targets);
    if (!l->targets)
        return 1;
    for (uint32_t i = 0; i < s->n_spheres; i++) {
        const rt_sphere *sp = &s->spheres[i];
        if (s->materials[sp->material].kind == RT_MAT_DIELECTRIC) {
            l->targets[l->nt] = sphere_light(RT_SHAPE_SPHERE, i, sp->center, sp->center, sp->radius);
            l->targets[l->nt++].prob = 1.0 / nt;
        }
    }
    return 0;
}

int rt_lights_build(rt_lights **out, const rt_scene *s, rt_lights_rule rule)
{
    *out = NULL;
    const size_t most = (size_t)s->n_spheres + s->shapes.quads.n + s->shapes.movers.n;
    light *items = malloc((most ? most : 1) * sizeof *items);
    if (!items)
        return RT_ENOMEM;
    uint32_t n = 0; /* in key order: spheres, quads, movers (rt_shape_kind), each by index */
    for (uint32_t i = 0; i < s->n_spheres; i++) {
        const rt_sphere *sp = &s->spheres[i];
        add(items, &n, sphere_light(RT_SHAPE_SPHERE, i, sp->center, sp->center, sp->radius), s,
            sp->material);
    }
    for (uint32_t i = 0; i < s->shapes.quads.n; i++)
        add(items, &n, quad_light(i, &s->shapes.quads.items[i]), s, s->shapes.quads.items[i].material);
    for (uint32_t i = 0; i < s->shapes.movers.n; i++) {
        const rt_mover *m = &s->shapes.movers.items[i];
        add(items, &n, sphere_light(RT_SHAPE_MOVER, i, m->center0, m->center1, m->radius), s, m->material);
    }
    if (!n) {
        free(items);
        return RT_OK;
    }
    rt_lights *l = calloc(1, sizeof *l);
    double *cdf = malloc(n * sizeof *cdf);
    if (!l || !cdf) {
        free(items), free(l), free(cdf);
        return RT_ENOMEM;
    }
    if (targets(l, s)) {
        free(items), free(l), free(cdf);
        return RT_ENOMEM;
    }
    double total = 0;
    for (uint32_t i = 0; i < n; i++)
        total += rule == RT_LIGHTS_UNIFORM ? 1.0 : items[i].prob;
    double acc = 0;
    for (uint32_t i = 0; i < n; i++) {
        items[i].prob = (rule == RT_LIGHTS_UNIFORM ? 1.0 : items[i].prob) / total;
        acc += items[i].prob;
        cdf[i] = acc;
    }
    cdf[n - 1] = 1.0;
    l->items = items;
    l->cdf = cdf;
    l->n = n;
    *out = l;
    return RT_OK;
}

void rt_lights_free(rt_lights *l)
{
    if (!l)
        return;
    free(l->items);
    free(l->cdf);
    free(l->targets);
    free(l);
}

uint32_t rt_lights_count(const rt_lights *l) { return l ? l->n : 0; }

uint32_t rt_lights_target_count(const rt_lights *l) { return l ? l->nt : 0; }

size_t rt_lights_bytes(const rt_lights *l)
{
    return l ? sizeof *l + l->n * (sizeof *l->items + sizeof *l->cdf) + l->nt * sizeof *l->targets : 0;
}

static int is_quad(const light *L) { return (uint32_t)(L->key >> 32) == RT_SHAPE_QUAD; }

static rt_vec3 centre(const light *L, double time) { return rt_v3_add(L->a, rt_v3_scale(rt_v3_sub(L->b, L->a), time)); }

/* 1 - cos of the half-angle of the cone a sphere of squared radius r2 at
 * squared distance d2 (> r2) subtends, without cancellation. */
static double cone_omc(double r2, double d2)
{
    const double sin2 = r2 / d2;
    return sin2 / (1.0 + sqrt(1.0 - sin2));
}

/* 1 - cos of the half-angle of the cone sphere L subtends from p (> 0), or
 * 0 when p is inside it. *w: the unit direction to its centre. */
static double cone(const light *L, rt_vec3 p, double time, rt_vec3 *w)
{
    const rt_vec3 d = rt_v3_sub(centre(L, time), p);
    const double d2 = rt_v3_len2(d), r = L->c.x;
    if (!(d2 > r * r))
        return 0.0;
    *w = rt_v3_scale(d, 1.0 / sqrt(d2));
    return cone_omc(r * r, d2);
}

/* The direction density of quad L from p for a ray that meets it at
 * distance t along unit direction dir. */
static double quad_pdf(const light *L, rt_vec3 dir, double t)
{
    const double c = fabs(rt_v3_dot(dir, L->n));
    return c > 0.0 ? t * t / (c * L->area) : 0.0;
}

/* A direction *dir toward sphere L from p, uniform in the cone it
 * subtends (its density in *pdf, L's choice included), by the fractions s
 * and the 32-bit turn t. Returns 0 when p is inside the sphere. */
static int cone_dir(const light *L, rt_vec3 p, double time, double s, uint32_t t, rt_vec3 *dir, double *pdf)
{
    rt_vec3 w;
    const double omc_max = cone(L, p, time, &w);
    if (omc_max == 0.0)
        return 0;
    /* cos theta uniform in [cos max, 1]: 1 - cos = s (1 - cos max); the
     * azimuth by turns; a frame around w (Duff et al.'s, branch on sign) */
    const double omc = s * omc_max, sin_t = sqrt(omc * (2.0 - omc)), cos_t = 1.0 - omc;
    double cph, sph;
    rt_sample_cos_sin_turn(t, &cph, &sph);
    const double sign = w.z >= 0.0 ? 1.0 : -1.0, a = -1.0 / (sign + w.z), b = w.x * w.y * a;
    const rt_vec3 t1 = rt_v3(1.0 + sign * w.x * w.x * a, sign * b, -sign * w.x);
    const rt_vec3 t2 = rt_v3(b, sign + w.y * w.y * a, -w.y);
    *dir = rt_v3_add(rt_v3_scale(w, cos_t), rt_v3_add(rt_v3_scale(t1, sin_t * cph), rt_v3_scale(t2, sin_t * sph)));
    *pdf = L->prob / (2.0 * PI * omc_max);
    return 1;
}

/* The light u in [0, 1) chooses (the first whose cdf passes u), and u's
 * fraction within its share. */
static uint32_t choose(const rt_lights *l, double u, double *rest)
{
    uint32_t lo = 0, hi = l->n - 1;
    while (lo < hi) {
        const uint32_t mid = (lo + hi) / 2;
        if (l->cdf[mid] > u)
            hi = mid;
        else
            lo = mid + 1;
    }
    const double below = lo ? l->cdf[lo - 1] : 0.0, r = (u - below) / l->items[lo].prob;
    *rest = r < 1.0 ? (r > 0.0 ? r : 0.0) : 0x1.fffffffffffffp-1;
    return lo;
}

int rt_lights_point(const rt_lights *l, double time, double u, uint64_t u2, rt_light_point *out)
{
    const uint32_t lo = choose(l, u, &out->rest);
    const light *L = &l->items[lo];
    out->kind = (uint32_t)(L->key >> 32);
    out->index = (uint32_t)L->key;
    out->material = L->material;
    out->emit = L->emit;
    out->one_sided = L->one_sided;
    if (is_quad(L)) {
        out->p = rt_v3_madd(rt_v3_madd(L->a, L->b, rt_warp_unit((uint32_t)(u2 >> 32))), L->c,
                            rt_warp_unit((uint32_t)u2));
        out->n = L->n;
        out->pdf = L->prob / L->area;
        return L->area > 0.0;
    }
    const double r = L->c.x; /* a sphere: uniform over its whole surface */
    out->n = rt_warp_sphere(u2);
    out->p = rt_v3_add(centre(L, time), rt_v3_scale(out->n, r));
    out->pdf = L->prob / (4.0 * PI * r * r);
    return r > 0.0;
}

int rt_lights_sample(const rt_lights *l, rt_vec3 p, double time, double u, uint64_t u2, rt_light_dir *out)
{
    const uint32_t lo = choose(l, u, &out->rest);
    const light *L = &l->items[lo];
    out->kind = (uint32_t)(L->key >> 32);
    out->index = (uint32_t)L->key;
    out->material = L->material;
    out->light = lo;
    out->emit = L->emit;
    const double s = rt_warp_unit((uint32_t)(u2 >> 32));
    if (is_quad(L)) {
        const rt_vec3 x = rt_v3_madd(rt_v3_madd(L->a, L->b, s), L->c, rt_warp_unit((uint32_t)u2));
        const rt_vec3 d = rt_v3_sub(x, p);
        const double len = rt_v3_len(d), facing = rt_v3_dot(d, L->n);
        if (!(len > 0.0) || facing == 0.0 || (L->one_sided && facing > 0.0))
            return 0; /* p in its plane, or behind a face that emits nothing toward it: no shadow ray */
        out->dir = rt_v3_scale(d, 1.0 / len);
        out->pdf = L->prob * quad_pdf(L, out->dir, len);
        return 1;
    }
    return cone_dir(L, p, time, s, (uint32_t)u2, &out->dir, &out->pdf);
}

/* The slot of light (kind, index) in the list (sorted by key), or l->n. */
static uint32_t slot_of(const rt_lights *l, uint32_t kind, uint32_t index)
{
    const uint64_t key = (uint64_t)kind << 32 | index;
    uint32_t lo = 0, hi = l->n;
    while (lo < hi) {
        const uint32_t mid = (lo + hi) / 2;
        if (l->items[mid].key < key)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < l->n && l->items[lo].key == key ? lo : l->n;
}

double rt_lights_pdf(const rt_lights *l, rt_vec3 p, double time, rt_vec3 dir, uint32_t kind, uint32_t index,
                     double t)
{
    const uint32_t lo = slot_of(l, kind, index);
    return lo < l->n ? rt_lights_pdf_of(l, lo, p, time, dir, t) : 0.0;
}

double rt_lights_area_pdf(const rt_lights *l, uint32_t kind, uint32_t index)
{
    const uint32_t lo = slot_of(l, kind, index);
    return lo < l->n ? l->items[lo].prob / l->items[lo].area : 0.0;
}

uint32_t rt_lights_quads(const rt_lights *l, rt_light_quads *q)
{
    if (!l || !l->n || l->n > RT_LIGHTS_QUAD_ROWS)
        return 0;
    for (uint32_t i = 0; i < l->n; i++) {
        const light *L = &l->items[i];
        if (!is_quad(L))
            return 0;
        const rt_vec3 v[4] = {L->a, L->b, L->c, L->n};
        double(*rows[4])[RT_LIGHTS_QUAD_ROWS] = {q->a, q->b, q->c, q->n};
        for (int k = 0; k < 4; k++) {
            rows[k][0][i] = v[k].x;
            rows[k][1][i] = v[k].y;
            rows[k][2][i] = v[k].z;
        }
        q->area[i] = L->area;
        q->prob[i] = L->prob;
        q->emit[i] = L->emit;
        q->cdf[i] = l->cdf[i];
        q->one_sided[i] = L->one_sided ? 1.0 : 0.0;
        q->quad[i] = (int64_t)(uint32_t)L->key;
    }
    return l->n;
}

double rt_lights_pdf_of(const rt_lights *l, uint32_t slot, rt_vec3 p, double time, rt_vec3 dir, double t)
{
    const light *L = &l->items[slot];
    if (is_quad(L))
        return L->prob * quad_pdf(L, dir, t);
    rt_vec3 w;
    const double omc_max = cone(L, p, time, &w);
    return omc_max > 0.0 ? L->prob / (2.0 * PI * omc_max) : 0.0;
}

int rt_lights_target_sample(const rt_lights *l, rt_vec3 p, double time, uint32_t a, uint32_t b, rt_vec3 *dir)
{
    const uint64_t x = (uint64_t)a * l->nt; /* the target: x's high word; its low word, a fraction left */
    double pdf;
    return cone_dir(&l->targets[x >> 32], p, time, rt_warp_unit((uint32_t)x), b, dir, &pdf);
}

double rt_lights_target_pdf(const rt_lights *l, rt_vec3 p, double time, rt_vec3 dir)
{
    (void)time; /* the targets are static spheres: centre a */
    double sum = 0;
    for (uint32_t i = 0; i < l->nt; i++) {
        const light *L = &l->targets[i];
        const rt_vec3 d = rt_v3_sub(L->a, p);
        const double b = rt_v3_dot(dir, d), r2 = L->c.x * L->c.x, d2 = rt_v3_len2(d);
        if (!(b > 0.0) || b * b < rt_v3_len2(dir) * (d2 - r2) || !(d2 > r2))
            continue; /* the line misses the sphere (or points away), or p is inside it */
        sum += L->prob / (2.0 * PI * cone_omc(r2, d2)); /* cone()'s, without its axis */
    }
    return sum;
}

uint32_t rt_lights_target_sphere(const rt_lights *l, uint32_t k) { return (uint32_t)l->targets[k].key; }

int rt_lights_target_between(const rt_lights *l, rt_vec3 x, double reach, uint32_t *target)
{
    for (uint32_t k = 0; k < l->nt; k++) {
        const rt_vec3 cx = rt_v3_sub(l->targets[k].a, x);
        const double rr = reach * l->targets[k].c.x * reach * l->targets[k].c.x, c2 = rt_v3_len2(cx);
        for (uint32_t j = 0; j < l->n; j++) {
            const rt_vec3 lx = rt_v3_sub(l->items[j].bc, x);
            const double d = rt_v3_dot(cx, lx), l2 = rt_v3_len2(lx);
            /* the centre's foot on the segment, within reach of the line: d^2 / l2 its squared
             * distance along the line, c2 - d^2 / l2 across it (times l2, no division) */
            if (d > 0.0 && d < l2 && c2 * l2 - d * d < rr * l2) {
                *target = k;
                return 1;
            }
        }
    }
    return 0;
}
