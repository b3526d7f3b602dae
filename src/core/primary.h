/* primary.h - candidate lists for camera rays.
 *
 * Every camera ray of a pixel leaves a point of the lens disk towards a point
 * of the pixel's footprint on the focus plane, so all the rays of a tile of
 * pixels lie in one known volume: the pinhole pyramid through the tile's
 * footprint, widened by the lens. rt_primary_build lists, per tile, the
 * spheres that reach into that volume (a conservative test, with margins far
 * above rounding), in order of the least distance at which any camera ray can
 * meet them. A camera ray then tests its tile's spheres in that order and
 * stops at the first whose least distance is beyond its closest hit: no
 * traversal. The answer is rt_sphere_closer's rule over the spheres tested,
 * and a sphere left out can neither be hit nor be closer, so it is the same
 * hit, to the bit, that brute force and the BVH find. Tiles whose list would
 * be long (rays grazing the field of spheres towards the horizon) are left
 * without one, and their rays go to the BVH. */
#ifndef RT_PRIMARY_H
#define RT_PRIMARY_H

#include <stddef.h>
#include <stdint.h>

#include "accel.h"
#include "camera.h"
#include "scene.h"

/* Tiles of 8x8 pixels, or larger powers of two for images so large that
 * there would be more than RT_PRIMARY_MAX_TILES of them: with at most 16
 * spheres a list, the lists never take more than 9 MB on a rank, whatever
 * the image size (109 KiB for the final scene at 600x400). */
#define RT_PRIMARY_TILE 8
#define RT_PRIMARY_MAX_TILES 65536u

/* A sphere in a tile's list: no camera ray of the tile meets it at a t
 * below lo (rounded down to a float). */
typedef struct rt_primary_entry {
    float lo;
    uint32_t sphere; /* index in the scene */
} rt_primary_entry;

typedef struct rt_primary {
    const rt_sphere *spheres; /* the scene's, which must outlive the lists */
    uint32_t width, height, tiles_x, tiles_y;
    uint32_t shift; /* a tile is 2^shift pixels square */
    struct {
        uint32_t first; /* in cand */
        int32_t n;      /* spheres in the list; -1: the tile has no list */
    } *tile;
    rt_primary_entry *cand; /* the lists, each by increasing lo */
    size_t n_cand;
} rt_primary;

/* Builds the lists for the camera rays of a width x height image taken with
 * cam (as rt_camera_init set it up for that image's aspect). Status code. */
int rt_primary_build(rt_primary **out, const rt_scene *s, const rt_camera *cam, uint32_t width, uint32_t height);
void rt_primary_free(rt_primary *p);
size_t rt_primary_bytes(const rt_primary *p);
/* Tiles with a list, and the spheres in the lists, for the summary. */
void rt_primary_stats(const rt_primary *p, uint32_t *tiles, uint32_t *listed, size_t *candidates);

/* The inward unit normals of the four side planes of the pyramid from
 * cam's lens centre through the points lower_left + s horizontal + t
 * vertical with s in [s0, s1], t in [t0, t1] (the camera rays' targets on
 * the focus plane): the lists' geometry, shared with the world's
 * (world_lists.c). */
void rt_primary_pyramid(const rt_camera *cam, double s0, double s1, double t0, double t1, rt_vec3 n[4]);

/* f rounded down to a float (a list's bound must never rise). */
float rt_primary_float_below(double f);

/* The list of pixel (x, y)'s tile: its length (-1 when the tile has no
 * list), and its start in p->cand through *first. */
static inline int32_t rt_primary_tile(const rt_primary *p, uint32_t x, uint32_t y, uint32_t *first)
{
    const uint32_t t = (y >> p->shift) * p->tiles_x + (x >> p->shift);
    *first = p->tile[t].first;
    return p->tile[t].n;
}

/* The closest hit with tmin < t <= tmax of a camera ray of a pixel whose
 * tile's list is (first, n >= 0) (rt_primary_tile): rt_accel_closest's
 * answer. (A function of its own, which the release build's LTO inlines into
 * the path loop, so that scripts/profile.sh counts it apart.) */
int rt_primary_closest(const rt_primary *p, uint32_t first, int32_t n, const rt_ray *ray, double tmin, double tmax,
                       rt_hit *hit);

#endif
