/* caustic.c - next-event estimation through a glass sphere (caustic.h). */
#include "caustic.h"

#include <math.h>

#include "core_internal.h"
#include "lights.h"
#include "nee.h"
#include "world.h"

#define T_MIN 0.001 /* path.h's shadow-acne bias */
#define PI 3.14159265358979323846
/* The gate's reach (rt_lights_target_between), in the sphere's radii:
 * measured on book3-final (128 x 128, 8 / 16 / 64 spp, display-space
 * RMSE against a 2,048-spp reference), a reach of the light's whole
 * penumbra (the light's half-diagonal added along the line) gave
 * 12.77 / 9.39 / 4.73, 0.6 and 0.45 the same to 0.01, 0.3 12.88 / 9.49 /
 * 4.83; each step down fewer vertices that estimate (the gate's cost
 * stays, about 90 instructions a lambertian vertex by callgrind). */
#define RT_CAUSTIC_REACH 0.5
#define SCAN 8        /* offsets tried across the sphere for sign changes */
#define REFINE 16     /* Illinois steps at most per root */
#define EXTREMUM 16   /* golden-section steps at most per turn of g */

typedef struct glass {
    rt_vec3 c;
    double r, eta, inv_r, inv_eta;
    uint32_t index;
} glass;

static glass glass_of(const rt_renderer *r, uint32_t target)
{
    const uint32_t i = rt_lights_target_sphere(r->lights, target);
    const rt_sphere *sp = &r->scene->spheres[i];
    const double eta = r->scene->materials[sp->material].ior;
    return (glass){sp->center, fabs(sp->radius), eta, 1.0 / fabs(sp->radius), 1.0 / eta, i};
}

int rt_caustic_gate(const rt_renderer *r, rt_vec3 x, uint32_t *target)
{
    /* a hollow sphere (negative radius: its normals inward) is no lens: its paths keep their light */
    return rt_lights_target_between(r->lights, x, RT_CAUSTIC_REACH, target) &&
           r->scene->spheres[rt_lights_target_sphere(r->lights, *target)].radius > 0.0;
}

/* The chain in the plane of x, the sphere's centre c (the origin) and
 * the light point: x at (-D, 0), the ray from x at offset b (its
 * distance from c, signed), unit direction w = (ca, b / D). It enters at
 * p1 at incidence cos ci (sin b / r), bends by beta = thi - tht toward c
 * (sin tht = b / (eta r)), leaves at p2 turned by 2 beta. */
typedef struct chain2 {
    double wx, wy, p1x, p1y, d1x, d1y, p2x, p2y, d2x, d2y;
    double ci, ct, t1, t2;
} chain2;

static int chain_at(const glass *g, double D, double b, chain2 *k)
{
    const double sa = b / D, si = b * g->inv_r, st = si * g->inv_eta;
    if (!(fabs(si) < 1.0))
        return 0;
    const double ca = sqrt(1.0 - sa * sa), ci = sqrt(1.0 - si * si), ct = sqrt(1.0 - st * st);
    const double cb = ci * ct + si * st, sb = si * ct - ci * st; /* cos, sin of beta */
    const double c2 = cb * cb - sb * sb, s2 = 2.0 * sb * cb;
    k->wx = ca;
    k->wy = sa;
    k->t1 = D * ca - g->r * ci;
    k->p1x = -D + k->t1 * ca;
    k->p1y = k->t1 * sa;
    k->d1x = ca * cb + sa * sb; /* w turned clockwise by beta */
    k->d1y = -ca * sb + sa * cb;
    k->t2 = -2.0 * (k->p1x * k->d1x + k->p1y * k->d1y);
    k->p2x = k->p1x + k->t2 * k->d1x;
    k->p2y = k->p1y + k->t2 * k->d1y;
    k->d2x = ca * c2 + sa * s2;
    k->d2y = -ca * s2 + sa * c2;
    k->ci = ci;
    k->ct = ct;
    return k->t1 > T_MIN && k->t2 > T_MIN;
}

/* The plane: u from x toward the centre (at distance D), e across it
 * toward the light point y, which is (yu, ye) from the centre. */
typedef struct plane {
    rt_vec3 x, u, e;
    double D, yu, ye;
} plane;

/* The signed distance of y from the exit ray of the chain at offset b; 0
 * (no value) when the chain fails or y lies behind its exit. */
static int g_of(const glass *g, const plane *P, double b, double *val)
{
    chain2 k;
    if (!chain_at(g, P->D, b, &k))
        return 0;
    const double yx = P->yu - k.p2x, yy = P->ye - k.p2y;
    if (!(yx * k.d2x + yy * k.d2y > 0.0))
        return 0;
    *val = k.d2x * yy - k.d2y * yx;
    return 1;
}

/* The root of g_of between offsets a (value fa) and b (fb) of opposite
 * signs, by the Illinois method. */
static double refine(const glass *g, const plane *P, double a, double fa, double b, double fb)
{
    int side = 0;
    for (int i = 0; i < REFINE; i++) {
        const double m = (a * fb - b * fa) / (fb - fa);
        double fm;
        if (!(m > fmin(a, b) && m < fmax(a, b)) || !g_of(g, P, m, &fm))
            break;
        if (fabs(fm) < 1e-6 * g->r)
            return m;
        if ((fm < 0.0) == (fb < 0.0)) {
            b = m;
            fb = fm;
            if (side == -1)
                fa *= 0.5;
            side = -1;
        } else {
            a = m;
            fa = fm;
            if (side == 1)
                fb *= 0.5;
            side = 1;
        }
    }
    return fabs(fa) < fabs(fb) ? a : b;
}

/* The extremum of g_of within (a, b) toward zero (its maximum when the
 * samples are negative, low = 1, else its minimum), by golden-section
 * search: *be, *fe. Returns 0 when a probe leaves the chain's domain. */
static int extremum(const glass *g, const plane *P, double a, double b, int low, double *be, double *fe)
{
    const double q = 0.38196601125010515; /* 2 - the golden ratio */
    double c = a + q * (b - a), d = b - q * (b - a), fc, fd;
    if (!g_of(g, P, c, &fc) || !g_of(g, P, d, &fd))
        return 0;
    for (int i = 0; i < EXTREMUM; i++) {
        if (low ? fc > fd : fc < fd) { /* the extremum is in (a, d) */
            b = d;
            d = c;
            fd = fc;
            c = a + q * (b - a);
            if (!g_of(g, P, c, &fc))
                return 0;
        } else {
            a = c;
            c = d;
            fc = fd;
            d = b - q * (b - a);
            if (!g_of(g, P, d, &fd))
                return 0;
        }
        if ((fc < 0.0) != low || (fd < 0.0) != low)
            break; /* crossed zero: a pair of roots about it */
    }
    const int pick_c = (fc < 0.0) != low || ((fd < 0.0) == low && (low ? fc > fd : fc < fd));
    *be = pick_c ? c : d;
    *fe = pick_c ? fc : fd;
    return 1;
}

static rt_vec3 in3(const plane *P, rt_vec3 c, double px, double py)
{
    return rt_v3_add(c, rt_v3_add(rt_v3_scale(P->u, px), rt_v3_scale(P->e, py)));
}
static rt_vec3 dir3(const plane *P, double dx, double dy)
{
    return rt_v3_add(rt_v3_scale(P->u, dx), rt_v3_scale(P->e, dy));
}

/* How a point y on the light's plane (normal nl) moves with the exit ray
 * that meets it, given the velocity v of the ray's point at y: v less its
 * part along the ray that keeps y on the plane. */
static rt_vec3 on_plane(rt_vec3 v, rt_vec3 d2, rt_vec3 nl)
{
    return rt_v3_madd(v, d2, -rt_v3_dot(v, nl) / rt_v3_dot(d2, nl));
}

/* The solid angle at x per unit of the light's area (normal nl) about the
 * chain at offset b (k) that meets the light at y, ty along its exit ray:
 * directions by (b, the turn phi about the axis x-c), dw = |b| / (D^2 ca)
 * db dphi; the point's motion with b by central differences, with phi
 * exactly (a turn about the axis). 0 when a neighbour fails. */
static double jacobian(const glass *g, const plane *P, const chain2 *k, double b, rt_vec3 y, double ty, rt_vec3 nl)
{
    const double h = 1e-6 * g->r;
    chain2 k0, k1;
    if (!chain_at(g, P->D, b - h, &k0) || !chain_at(g, P->D, b + h, &k1))
        return 0.0;
    const rt_vec3 d2 = dir3(P, k->d2x, k->d2y);
    const rt_vec3 dp = dir3(P, (k1.p2x - k0.p2x) / (2 * h), (k1.p2y - k0.p2y) / (2 * h));
    const rt_vec3 dd = dir3(P, (k1.d2x - k0.d2x) / (2 * h), (k1.d2y - k0.d2y) / (2 * h));
    const rt_vec3 yb = on_plane(rt_v3_madd(dp, dd, ty), d2, nl);
    const rt_vec3 yphi = on_plane(rt_v3_cross(P->u, rt_v3_sub(y, g->c)), d2, nl);
    const double area = rt_v3_len(rt_v3_cross(yb, yphi));
    return area > 0.0 ? fabs(b) / (P->D * P->D * k->wx) / area : 0.0;
}

static double transmission(const glass *g, const chain2 *k)
{
    return (1.0 - rt_material_reflectance(k->ci, g->inv_eta)) * (1.0 - rt_material_reflectance(k->ct, g->eta));
}

/* The power heuristic's weight of density a against b. */
static double power(double a, double b) { return a * a / (a * a + b * b); }

/* The light of the chain at offset b, or zero: weighed by multiple
 * importance sampling against the scattered path that finds the same
 * chain (its density the scattering's times the two refractions' chances). */
static rt_vec3 chain_light(const rt_renderer *r, const glass *g, const plane *P, rt_vec3 n, double b,
                           const rt_light_point *lp, double time, uint64_t *segments)
{
    const rt_vec3 none = {0, 0, 0};
    chain2 k;
    if (!chain_at(g, P->D, b, &k))
        return none;
    const rt_vec3 w = dir3(P, k.wx, k.wy), d2 = dir3(P, k.d2x, k.d2y);
    const double cosine = rt_v3_dot(w, n), dn = rt_v3_dot(d2, lp->n);
    if (!(cosine > 0.0) || dn == 0.0 || (lp->one_sided && !(dn < 0.0)))
        return none;
    const rt_ray out = {in3(P, g->c, k.p2x, k.p2y), d2};
    double ty;
    if (!rt_world_shape_t(r->world, lp->kind, lp->index, &out, time, T_MIN, &ty))
        return none;
    const double J = jacobian(g, P, &k, b, rt_ray_at(&out, ty), ty, lp->n);
    if (!(J > 0.0))
        return none;
    *segments += 3;
    const rt_ray in = {P->x, w}, inside = {in3(P, g->c, k.p1x, k.p1y), dir3(P, k.d1x, k.d1y)};
    if (rt_world_occluded(r->world, &in, time, T_MIN, k.t1, RT_SHAPE_SPHERE, g->index) ||
        rt_world_occluded(r->world, &inside, time, T_MIN, k.t2, RT_SHAPE_SPHERE, g->index) ||
        rt_world_occluded(r->world, &out, time, T_MIN, ty, lp->kind, lp->index))
        return none;
    const double trans = transmission(g, &k);
    const double mis = power(lp->pdf / J, rt_nee_scatter_pdf(r, P->x, n, time, w) * trans);
    const rt_material *m = &r->scene->materials[lp->material];
    return rt_v3_scale(m->emit, cosine / PI * trans * J / lp->pdf * mis);
}

/* The plane of x, the centre and y; 0 when y is on the axis. */
static int plane_of(const glass *g, rt_vec3 x, rt_vec3 y, plane *P)
{
    const rt_vec3 cx = rt_v3_sub(g->c, x), cy = rt_v3_sub(y, g->c);
    P->x = x;
    P->D = rt_v3_len(cx);
    if (!(P->D > g->r))
        return 0;
    P->u = rt_v3_scale(cx, 1.0 / P->D);
    P->yu = rt_v3_dot(cy, P->u);
    const rt_vec3 across = rt_v3_madd(cy, P->u, -P->yu);
    P->ye = rt_v3_len(across);
    if (!(P->ye > 1e-9 * P->D))
        return 0; /* a measure-zero case */
    P->e = rt_v3_scale(across, 1.0 / P->ye);
    return 1;
}

double rt_caustic_weight(const rt_renderer *r, rt_vec3 x, rt_vec3 n, rt_vec3 w, uint32_t target, const rt_whit *h,
                         rt_vec3 y, rt_vec3 nl, double time)
{
    if (r->scene->materials[h->material].texture)
        return 1.0; /* rt_caustic_direct leaves textured lights to the scattered paths */
    const glass g = glass_of(r, target);
    plane P;
    if (!plane_of(&g, x, y, &P))
        return 1.0;
    const rt_vec3 wu = rt_v3_unit(w);
    const double b = P.D * rt_v3_dot(wu, P.e);
    chain2 k;
    if (!chain_at(&g, P.D, b, &k))
        return 1.0;
    const double ty = rt_v3_len(rt_v3_sub(y, in3(&P, g.c, k.p2x, k.p2y)));
    const double J = jacobian(&g, &P, &k, b, y, ty, nl);
    if (!(J > 0.0))
        return 1.0;
    const double pm = rt_lights_area_pdf(r->lights, h->kind, h->index) / J;
    return power(rt_nee_scatter_pdf(r, x, n, time, w) * transmission(&g, &k), pm);
}

rt_vec3 rt_caustic_direct(const rt_renderer *r, rt_vec3 x, rt_vec3 n, rt_vec3 weight, double time, uint32_t target,
                          double u, uint64_t u2, uint64_t *segments)
{
    const rt_vec3 none = {0, 0, 0};
    rt_light_point lp;
    if (!rt_lights_point(r->lights, time, u, u2, &lp) || r->scene->materials[lp.material].texture)
        return none;
    const glass g = glass_of(r, target);
    plane P;
    if (!plane_of(&g, x, lp.p, &P))
        return none;
    /* every root: a sign change between two offsets of the scan, and a
     * pair of roots about an extremum of g between them (where the chains
     * fold, near the caustic's bright edge), found by a golden-section
     * search of the extremum when three samples turn */
    double bs[SCAN + 1], fs[SCAN + 1];
    int oks[SCAN + 1];
    for (int k = 0; k <= SCAN; k++) {
        const double v = -1.0 + 2.0 * k / SCAN, e = 1.0 - fabs(v); /* denser toward grazing, where g turns fast */
        bs[k] = g.r * (v < 0.0 ? -1.0 : 1.0) * (1.0 - e * e) * (1.0 - 1e-9);
        fs[k] = 0.0;
        oks[k] = g_of(&g, &P, bs[k], &fs[k]);
    }
    rt_vec3 sum = none;
    for (int k = 1; k <= SCAN; k++) {
        if (!oks[k] || !oks[k - 1])
            continue;
        if ((fs[k] < 0.0) != (fs[k - 1] < 0.0)) {
            sum = rt_v3_add(sum, chain_light(r, &g, &P, n, refine(&g, &P, bs[k - 1], fs[k - 1], bs[k], fs[k]), &lp,
                                             time, segments));
            continue;
        }
        if (k == SCAN || !oks[k + 1] || (fs[k + 1] < 0.0) != (fs[k] < 0.0))
            continue;
        const double d0 = fs[k] - fs[k - 1], d1 = fs[k + 1] - fs[k];
        if ((d0 < 0.0) == (d1 < 0.0) || (fs[k] > 0.0) == (d0 > 0.0))
            continue; /* no turn, or one away from zero */
        double be, fe;
        if (!extremum(&g, &P, bs[k - 1], bs[k + 1], fs[k] < 0.0, &be, &fe) || (fe < 0.0) == (fs[k] < 0.0))
            continue;
        sum = rt_v3_add(sum, chain_light(r, &g, &P, n, refine(&g, &P, bs[k - 1], fs[k - 1], be, fe), &lp, time,
                                         segments));
        sum = rt_v3_add(sum, chain_light(r, &g, &P, n, refine(&g, &P, be, fe, bs[k + 1], fs[k + 1]), &lp, time,
                                         segments));
    }
    return rt_v3_mul(weight, sum);
}
