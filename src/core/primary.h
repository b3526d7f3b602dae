/* primary.h - candidate lists for camera rays over the spheres (book 1's
 * path loop): tiles.h's lists, whose items are the scene's spheres. A
 * camera ray tests its tile's spheres by rt_sphere_closer's rule, which
 * gives the same hit, to the bit, that brute force and the BVH find. */
#ifndef RT_PRIMARY_H
#define RT_PRIMARY_H

#include <stddef.h>
#include <stdint.h>

#include "accel.h"
#include "camera.h"
#include "scene.h"
#include "tiles.h"

typedef struct rt_primary {
    const rt_sphere *spheres; /* the scene's, which must outlive the lists */
    rt_tiles tiles;           /* entries' ids: indices of spheres */
} rt_primary;

/* Builds the lists for the camera rays of a width x height image taken with
 * cam (as rt_camera_init set it up for that image's aspect). Status code. */
int rt_primary_build(rt_primary **out, const rt_scene *s, const rt_camera *cam, uint32_t width, uint32_t height);
void rt_primary_free(rt_primary *p);
size_t rt_primary_bytes(const rt_primary *p);
/* Tiles with a list, and the spheres in the lists, for the summary. */
void rt_primary_stats(const rt_primary *p, uint32_t *tiles, uint32_t *listed, size_t *candidates);

/* The list of pixel (x, y)'s tile (rt_tiles_tile). */
static inline int32_t rt_primary_tile(const rt_primary *p, uint32_t x, uint32_t y, uint32_t *first)
{
    return rt_tiles_tile(&p->tiles, x, y, first);
}

/* The closest hit with tmin < t <= tmax of a camera ray of a pixel whose
 * tile's list is (first, n >= 0) (rt_primary_tile): rt_accel_closest's
 * answer. (A function of its own, which the release build's LTO inlines into
 * the path loop, so that scripts/profile.sh counts it apart.) */
int rt_primary_closest(const rt_primary *p, uint32_t first, int32_t n, const rt_ray *ray, double tmin, double tmax,
                       rt_hit *hit);

#endif
