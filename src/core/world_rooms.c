/* world_rooms.c - the closest hit of a ray that starts inside a glass
 * sphere, without the walk. Inside a glass sphere a ray can hit only the
 * sphere's far side and the few shapes that reach into its ball, so those
 * tests alone give the walk's answer, to the bit. In book2-final four rays
 * in ten start inside its glass sphere of blue smoke (they refract in, then
 * scatter in the smoke until the path ends), and each spared walk is some
 * 90 ns of a segment's 160.
 *
 * Why the answer is the walk's (and brute force's): the ray's origin o and
 * the sphere's hit point p both lie in the ball of radius r_in about the
 * centre (checked on every query), so the whole segment from o to p does
 * (a ball is convex). Every shape whose box keeps a margin m from that ball
 * lies out of the segment's reach: a shape's test accepts a point off its
 * surface by its rounding alone, far below m (m is 1e-4 of the radius plus
 * 1e-6 of the scene's extent, a tangent ray's root errs by about 1e-8 of
 * the extent). So no shape but the sphere and its near ones can give a t
 * up to the sphere's, and the least of their (t, item) by
 * rt_world_test_item's rule, which does not depend on the order, is the
 * walk's. When a check fails (the origin outside, the ray leaving the
 * sphere from its outer face, a sphere with too many near shapes), the walk
 * answers. */
#include "world_internal.h"

#include <math.h>
#include <stdlib.h>

#include "status.h"

/* Rooms at most: the largest glass spheres get them (each costs a pass over
 * the items' boxes at the build). */
#define ROOMS_MAX 64

/* Squared distance from point c to box b. */
static double box_dist2(const wbox *b, rt_vec3 c)
{
    const double p[3] = {c.x, c.y, c.z};
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
        const double e = p[k] < b->lo[k] ? b->lo[k] - p[k] : p[k] > b->hi[k] ? p[k] - b->hi[k] : 0.0;
        d2 += e * e;
    }
    return d2;
}

/* Static sphere i's room in *rm when it is glass with at most RT_ROOM_NEAR
 * boxes near its ball; returns 1 if so. */
static int room_of_sphere(const rt_world *w, uint32_t i, const wbox *bx, double extent, room *rm)
{
    const uint32_t item = w->ns + i;
    const rt_sphere *sp = &w->s->spheres[i];
    const double r = fabs(sp->radius);
    if (w->s->materials[w->mat[item]].kind != RT_MAT_DIELECTRIC || !(r > 0.0) || !isfinite(r))
        return 0;
    const double r_in = r * (1.0 + 1e-9), r_out = r_in + 1e-4 * r + 1e-6 * extent;
    *rm = (room){.c = sp->center, .in2 = r_in * r_in, .item = item, .n_near = 0};
    for (uint32_t j = 0; j < w->nitems; j++) {
        if (j == item || !(box_dist2(&bx[j], sp->center) < r_out * r_out))
            continue;
        if (rm->n_near == RT_ROOM_NEAR)
            return 0;
        rm->near[rm->n_near++] = j;
    }
    return 1;
}

typedef struct glass {
    double r;
    uint32_t i;
} glass;

/* The larger radius first, then the lower index: which spheres get rooms
 * when there are more than ROOMS_MAX. */
static int by_radius(const void *a, const void *b)
{
    const glass *x = a, *y = b;
    return x->r > y->r ? -1 : x->r < y->r ? 1 : (x->i > y->i) - (x->i < y->i);
}

int rt_world_rooms_build(rt_world *w, const wbox *bx, double extent)
{
    const rt_scene *s = w->s;
    uint32_t n = 0;
    glass *g = malloc((s->n_spheres ? s->n_spheres : 1) * sizeof *g);
    if (!g)
        return RT_ENOMEM;
    for (uint32_t i = 0; i < s->n_spheres; i++)
        if (s->materials[w->mat[w->ns + i]].kind == RT_MAT_DIELECTRIC)
            g[n++] = (glass){fabs(s->spheres[i].radius), i};
    if (n > ROOMS_MAX)
        qsort(g, n, sizeof *g, by_radius);
    n = n < ROOMS_MAX ? n : ROOMS_MAX;
    int st = RT_OK;
    if (n) {
        w->rooms = malloc(n * sizeof *w->rooms);
        w->room_of = malloc(s->n_spheres * sizeof *w->room_of);
        st = w->rooms && w->room_of ? RT_OK : RT_ENOMEM;
    }
    for (uint32_t i = 0; i < s->n_spheres && n && !st; i++)
        w->room_of[i] = -1;
    for (uint32_t k = 0; k < n && !st; k++)
        if (room_of_sphere(w, g[k].i, bx, extent, &w->rooms[w->n_rooms])) {
            w->room_of[g[k].i] = (int32_t)w->n_rooms;
            w->n_rooms++;
        }
    free(g);
    if (!st && !w->n_rooms) {
        free(w->rooms), free(w->room_of);
        w->rooms = NULL, w->room_of = NULL;
    }
    return st;
}

int rt_world_closest_from(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax,
                          const rt_whit *from, rt_whit *hit)
{
    if (from && from->kind == RT_SHAPE_SPHERE && w->room_of && w->room_of[from->index] >= 0) {
        const room *rm = &w->rooms[w->room_of[from->index]];
        const rt_vec3 oc = rt_v3_sub(ray->orig, rm->c);
        double best_t = tmax;
        uint32_t best = UINT32_MAX;
        if (rt_v3_dot(oc, oc) <= rm->in2 && rt_world_test_item(w, rm->item, ray, time, tmin, &best_t, &best)) {
            const rt_vec3 pc = rt_v3_sub(rt_ray_at(ray, best_t), rm->c);
            if (rt_v3_dot(pc, pc) <= rm->in2) {
                for (uint32_t j = 0; j < rm->n_near; j++)
                    rt_world_test_item(w, rm->near[j], ray, time, tmin, &best_t, &best);
                return rt_world_hit_of(w, best_t, best, hit);
            }
        }
    }
    return w->closest(w, ray, time, tmin, tmax, hit);
}

uint32_t rt_world_rooms(const rt_world *w) { return w->n_rooms; }
