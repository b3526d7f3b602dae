/* scenes_book2.h - book 2's named scenes (scenes_book2.c), built for
 * scenes.c's table. */
#ifndef RT_SCENES_BOOK2_H
#define RT_SCENES_BOOK2_H

#include <stdint.h>

#include "scene.h"
#include "scenes.h"

/* Builds book-2 scene `name` into s (initialising it); its random content
 * and noise tables from seed; img: the earth's texels for the scenes that
 * need them (RT_ENOFILE without). RT_EINVAL for an unknown name. */
int rt_scenes_book2_build(rt_scene *s, const char *name, uint64_t seed, const rt_scene_image *img);

#endif
