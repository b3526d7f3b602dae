/* scenes.h - the book's named scenes: the final scene and the chapter scenes
 * the seeds render, looked up by name for --scene and --list-scenes. */
#ifndef RT_SCENES_H
#define RT_SCENES_H

#include <stdint.h>

#include "scene.h"

typedef struct rt_scene_info {
    const char *name;
    const char *summary; /* one line for --list-scenes */
    int book;            /* 1, 2 or 3: --list-scenes groups by it */
    /* The book's settings for the scene, the defaults of a job that renders
     * it (options override them); 0: the program's own defaults. */
    uint32_t width, height, samples, max_depth;
    int needs_earth; /* reads earthmap.jpg (rt_scene_image) */
} rt_scene_info;

/* An image a named scene uses (the book's earthmap.jpg): rank 0's app
 * layer reads the file (io/texture_image.h) and passes the texels, which
 * the builder copies into the scene. */
typedef struct rt_scene_image {
    uint32_t width, height;
    const uint8_t *texels; /* width * height x RGB, 8 bits, top row first */
} rt_scene_image;

/* Number of named scenes, and the i-th (NULL past the end), in list order. */
unsigned rt_scenes_count(void);
const rt_scene_info *rt_scenes_info(unsigned i);

/* Builds scene `name` into s. seed and grid matter only to the scenes that
 * draw random spheres or noise (final, book 2's); img only to those that
 * need the earth (rt_scene_info.needs_earth: RT_ENOFILE without it).
 * RT_EINVAL for an unknown name. */
int rt_scene_build_named(rt_scene *s, const char *name, uint64_t seed, int grid, const rt_scene_image *img);
/* The named scene `name`'s entry, NULL when unknown. */
const rt_scene_info *rt_scenes_find(const char *name);

#endif
