/* scenes.h - the book's named scenes: the final scene and the chapter scenes
 * the seeds render, looked up by name for --scene and --list-scenes. */
#ifndef RT_SCENES_H
#define RT_SCENES_H

#include <stdint.h>

#include "scene.h"

typedef struct rt_scene_info {
    const char *name;
    const char *summary; /* one line for --list-scenes */
} rt_scene_info;

/* Number of named scenes, and the i-th (NULL past the end), in list order. */
unsigned rt_scenes_count(void);
const rt_scene_info *rt_scenes_info(unsigned i);

/* Builds scene `name` into s. seed and grid matter only to the scenes that
 * draw random spheres (final). RT_EINVAL for an unknown name. */
int rt_scene_build_named(rt_scene *s, const char *name, uint64_t seed, int grid);

#endif
