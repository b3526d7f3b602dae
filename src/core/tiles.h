/* tiles.h - candidate lists for camera rays, by tiles of pixels: the
 * geometry and the lists, shared by book 1's over the spheres (primary.c)
 * and the book-2 loop's over the world's shapes (world_lists.c), which
 * each say what their items are and test them.
 *
 * Every camera ray of a pixel leaves a point of the lens disk towards a
 * point of the pixel's footprint on the focus plane, so all the rays of a
 * tile of pixels lie in one known volume: the pinhole pyramid through the
 * tile's footprint, widened by the lens. An item is listed for a tile unless
 * it lies beyond one of the pyramid's four side planes by more than its
 * reach (its size, the lens's reach over its depths, a margin far above
 * rounding), and the lists keep the items in order of the least t at which
 * a camera ray can meet them. A camera ray then tests its tile's items in
 * that order and stops at the first whose least t is beyond its closest
 * hit: no walk. An item left out can neither be hit nor be closer, so the
 * answer is the walk's and brute force's, to the bit. Tiles whose list
 * would be long go to the walk. Core layer. */
#ifndef RT_TILES_H
#define RT_TILES_H

#include <stddef.h>
#include <stdint.h>

#include "camera.h"

/* Tiles of 8x8 pixels, or larger powers of two for images so large that
 * there would be more than RT_TILES_MAX of them: with lists of at most a
 * few dozen items, the lists stay within megabytes whatever the image
 * size. */
#define RT_TILES_SIZE 8
#define RT_TILES_MAX 65536u

/* An item in a tile's list: no camera ray of the tile meets it at a t
 * below lo (rounded down to a float); id: the caller's (a sphere, an item
 * of the world). */
typedef struct rt_tile_entry {
    float lo;
    uint32_t id;
} rt_tile_entry;

typedef struct rt_tiles {
    uint32_t tiles_x, tiles_y;
    uint32_t shift; /* a tile is 2^shift pixels square */
    struct {
        uint32_t first; /* in cand */
        int32_t n;      /* items in the list; -1: the tile has no list */
    } *tile;
    rt_tile_entry *cand; /* the lists, each by increasing lo */
    size_t n_cand;
} rt_tiles;

/* An item as the build sees it: the least t at which a camera ray can meet
 * it, the caller's id, its box relative to the lens centre (a sphere's
 * centre twice, its radius in reach), and how far beyond a side plane it
 * can lie and still be met. */
typedef struct rt_tile_item {
    double lo;
    uint32_t id;
    double rlo[3], rhi[3];
    double reach;
} rt_tile_item;

/* The depth of cam's focus plane in front of its lens centre (the t = 1
 * of its rays), or 0 for a camera the lists cannot serve. */
double rt_tiles_focus(const rt_camera *cam);

/* Lists of at most cap items for the camera rays of a width x height image
 * of cam (its pixels mapped as the book-2 loop maps them with book2_pixels,
 * else as book 1's), from items[0, n) (reordered here). Status code;
 * rt_tiles_free frees them either way. */
int rt_tiles_build(rt_tiles *t, const rt_camera *cam, int book2_pixels, uint32_t width, uint32_t height,
                   rt_tile_item *items, uint32_t n, int32_t cap);
void rt_tiles_free(rt_tiles *t);
size_t rt_tiles_bytes(const rt_tiles *t);
/* Tiles with a list, and the items in the lists, for the summary. */
void rt_tiles_stats(const rt_tiles *t, uint32_t *tiles, uint32_t *listed, size_t *candidates);

/* The list of pixel (x, y)'s tile: its length (-1 when the tile has no
 * list), and its start in t->cand through *first. */
static inline int32_t rt_tiles_tile(const rt_tiles *t, uint32_t x, uint32_t y, uint32_t *first)
{
    const uint32_t k = (y >> t->shift) * t->tiles_x + (x >> t->shift);
    *first = t->tile[k].first;
    return t->tile[k].n;
}

#endif
