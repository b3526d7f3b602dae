/* world_internal.h - the world's layout, shared by its build (world.c) and
 * its closest-hit queries (world_closest.c, world_traverse.h); nothing else
 * includes it. */
#ifndef RT_WORLD_INTERNAL_H
#define RT_WORLD_INTERNAL_H

#include <math.h>
#include <stdint.h>

#include "fbox.h"
#include "scene.h"
#include "sphere.h"
#include "texture.h"
#include "world.h"

/* A quad with what its test needs: its plane (unit normal n, offset d)
 * and the vectors whose dot products with a point's offset from q give its
 * edge coordinates: with N = u x v and w = N / |N|^2, the book's
 * alpha = w . (p x v) = p . (v x w) and beta = w . (u x p) = p . (w x u). */
typedef struct quad_x {
    rt_vec3 q, n, ea, eb;
    double d;
} quad_x;

#define WWIDTH FBOX_WIDTH

/* An item's box in double (the build's; world.c). */
typedef struct wbox {
    double lo[3], hi[3];
} wbox;

/* Eight quads' rows for the flat test (world_flat.c): the corner, the
 * unit normal, the edge-coordinate vectors (quad_x's), the plane's
 * offset, and the items as doubles. A block's unused lanes have a zero
 * normal: their denominator is 0, below rt_quad_t's 1e-8, so they never
 * hit. */
#define RT_FLAT_WIDTH 8 /* one AVX-512 register of doubles */
typedef struct flat8 {
    _Alignas(64) double q[3][RT_FLAT_WIDTH];
    double n[3][RT_FLAT_WIDTH], ea[3][RT_FLAT_WIDTH], eb[3][RT_FLAT_WIDTH], d[RT_FLAT_WIDTH], item[RT_FLAT_WIDTH];
} flat8;

/* A node of the wide tree: its children's boxes in float, rounded outward
 * (fbox.h), rows x, y, z; a child is a node (code >= 0) or a leaf, item
 * ~code (a leaf holds one item: world.c's LEAF_ITEMS). */
typedef struct wide {
    _Alignas(64) float bmin[3][WWIDTH];
    float bmax[3][WWIDTH];
    int32_t child[WWIDTH];
    int32_t nchild; /* bit mask of the child slots in use */
} wide;

/* A glass sphere whose inside the closest-hit query answers without the
 * walk (world_rooms.c): its centre, the squared radius a ray's origin and
 * hit point must lie within, its item, and the few items whose boxes come
 * near its ball (the ones a ray from inside can hit before its far side). */
#define RT_ROOM_NEAR 8
typedef struct room {
    rt_vec3 c;
    double in2;
    uint32_t item, n_near;
    uint32_t near[RT_ROOM_NEAR];
} room;

/* rt_world_closest's and rt_world_occluded's work for the world's mode. */
typedef int (*rt_world_closest_fn)(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax,
                                   rt_whit *hit);
typedef int (*rt_world_occluded_fn)(const rt_world *w, const rt_ray *ray, double time, double tmin, double tmax,
                                    uint32_t item);

struct rt_world {
    const rt_scene *s;
    rt_world_closest_fn closest;   /* chosen once, at the end of the build (rt_world_pick) */
    rt_world_occluded_fn occluded; /* its item: the shape whose hit is at tmax */
    quad_x *quads;
    quad_x *hull; /* the media's boundary quads, prepared once */
    uint32_t nq, ns, nitems; /* items: quads 0..nq-1, the moving spheres nq..ns-1, then the static spheres */
    uint32_t *items;     /* leaf order (the build's) */
    uint32_t *mat;       /* each item's material, for the hits */
    wide *nodes;
    uint32_t n_nodes;
    int mode; /* rt_world_mode; RT_WORLD_BVH resolved to the AVX or SSE2 test at build */
    flat8 *flat; /* the quads eight to a block for the flat test (world_flat.c), or NULL */
    uint32_t n_flat;
    room *rooms;      /* the glass spheres' insides (world_rooms.c) */
    int32_t *room_of; /* each static sphere's room, or -1; NULL when there are none */
    uint32_t n_rooms;
    rt_perlin perlin;
    double t_lo, t_hi; /* the rays' times the moving spheres' boxes hold them for */
};

/* The item of shape (kind, index): the quads, then the moving spheres,
 * then the static spheres; and back. */
static inline uint32_t rt_world_item(const rt_world *w, uint32_t kind, uint32_t index)
{
    return kind == RT_SHAPE_QUAD ? index : kind == RT_SHAPE_MOVER ? w->nq + index : w->ns + index;
}
static inline void rt_world_shape(const rt_world *w, uint32_t item, uint32_t *kind, uint32_t *index)
{
    *kind = item < w->nq ? RT_SHAPE_QUAD : item < w->ns ? RT_SHAPE_MOVER : RT_SHAPE_SPHERE;
    *index = item < w->nq ? item : item < w->ns ? item - w->nq : item - w->ns;
}

/* Sets w's queries for its mode and tree (world_closest.c): the last step
 * of the build. */
void rt_world_pick(rt_world *w);

/* The flat test (world_flat.c): every quad at once, eight to an AVX-512
 * register. rt_world_flat_build lays the quads out for it (w->flat) when
 * the CPU has AVX-512 and the scene is one it is for (its size, and
 * leaves_per_ray: the tree's leaves a ray enters on average, world.c), or
 * with force whatever the scene (RT_WORLD_FLAT); else it leaves w->flat
 * NULL. Returns RT_OK or RT_ENOMEM. rt_world_flat_pick sets w's queries
 * to it. */
int rt_world_flat_build(rt_world *w, int force, double leaves_per_ray);
void rt_world_flat_pick(rt_world *w);

/* Item i's box (the tree's; a moving sphere's over the world's times). */
wbox rt_world_item_box(const rt_world *w, uint32_t i);

/* The rooms of w's glass spheres (world_rooms.c), from the items' boxes
 * (the build's, item by item) and the scene's extent (its largest
 * coordinate): none in brute-force mode. Returns RT_OK or
 * RT_ENOMEM. */
int rt_world_rooms_build(rt_world *w, const wbox *bx, double extent);

/* The book's quad test: the plane, then the edge coordinates in [0, 1]. */
static inline int rt_quad_t(const quad_x *q, const rt_ray *ray, double tmin, double tmax, double *t)
{
    const double denom = rt_v3_dot(q->n, ray->dir);
    if (fabs(denom) < 1e-8)
        return 0;
    const double tt = (q->d - rt_v3_dot(q->n, ray->orig)) / denom;
    if (!(tt > tmin && tt <= tmax))
        return 0;
    const rt_vec3 hp = rt_v3_sub(rt_ray_at(ray, tt), q->q);
    const double a = rt_v3_dot(hp, q->ea), b = rt_v3_dot(hp, q->eb);
    if (!(a >= 0 && a <= 1 && b >= 0 && b <= 1))
        return 0;
    *t = tt;
    return 1;
}

static inline rt_vec3 rt_mover_center(const rt_mover *m, double time)
{
    return rt_v3_add(m->center0, rt_v3_scale(rt_v3_sub(m->center1, m->center0), time));
}

/* Item i against the ray: replaces (*best_t, *best) when nearer, or as
 * near with a lower item (quads, then moving spheres, then static spheres:
 * the order of rt_world_closest's ties); returns 1 if it does. A static
 * sphere's t has rt_accel_closest's bits (sphere.h). */
static inline int rt_world_test_item(const rt_world *w, uint32_t i, const rt_ray *ray, double time, double tmin,
                                     double *best_t, uint32_t *best)
{
    double t;
    int hit;
    if (i < w->nq) {
        hit = rt_quad_t(&w->quads[i], ray, tmin, *best_t, &t);
    } else if (i < w->ns) {
        const rt_mover *m = &w->s->shapes.movers.items[i - w->nq];
        hit = rt_sphere_root(rt_mover_center(m, time), m->radius * m->radius, ray, rt_v3_len2(ray->dir), tmin, &t) &&
              t <= *best_t;
    } else {
        const rt_sphere *sp = &w->s->spheres[i - w->ns];
        hit = rt_sphere_root(sp->center, sp->radius * sp->radius, ray, rt_v3_len2(ray->dir), tmin, &t) &&
              t <= *best_t;
    }
    if (hit && (t < *best_t || i < *best)) {
        *best_t = t;
        *best = i;
        return 1;
    }
    return 0;
}

/* The hit of item best at best_t (UINT32_MAX: none), its kind, index and
 * material decoded; returns 1 on a hit. */
static inline __attribute__((always_inline)) int rt_world_hit_of(const rt_world *w, double best_t, uint32_t best,
                                                                 rt_whit *hit)
{
    if (best == UINT32_MAX)
        return 0;
    hit->t = best_t;
    rt_world_shape(w, best, &hit->kind, &hit->index);
    hit->material = w->mat[best];
    return 1;
}

#endif
