/* scene_json.h - scene files: the JSON scene format (camera, background,
 * textures, materials, spheres, quads, boxes, moving spheres, media,
 * groups and instances; see docs/SCENES_AND_FORMATS.md), read with cJSON and
 * written back so that dump -> load -> dump is byte-identical and a loaded
 * dump serializes to the very bytes of the scene it was dumped from.
 * Lives in its own library (rtscenejson) so the render core never links
 * cJSON. */
#ifndef RT_SCENE_JSON_H
#define RT_SCENE_JSON_H

#include <stddef.h>
#include <stdint.h>

#include "scene.h"

/* Format versions: 1 holds book 1's scenes (and is still written for
 * them), 2 everything; a file without "version" is version 1. */
#define RT_SCENE_JSON_VERSION 2
/* Largest scene file read: a dump takes about 200 bytes per sphere, so
 * about five million spheres (a --grid 1000 dump is 801 MB). */
#define RT_SCENE_JSON_MAX_BYTES (1024u << 20)

/* Where a scene's images come from: images[i] is the file image i was
 * read from (as this program opens it). Dumps refer to these files. */
typedef struct rt_scene_files {
    char **images;
    uint32_t n;
    size_t cap;
} rt_scene_files;

/* Appends a copy of path. */
int rt_scene_files_add(rt_scene_files *f, const char *path);
void rt_scene_files_free(rt_scene_files *f);

/* Reads and parses the file at path (messages name it as given); image
 * textures are read from paths relative to its directory, and their files
 * listed in *files when files is not NULL. RT_EIO when the file cannot be
 * read; RT_EFORMAT for bad content; an image's status (RT_ENOFILE,
 * RT_EIMAGE_*, texture_image.h) when an image cannot be used. */
int rt_scene_json_load(rt_scene *s, const char *path, rt_scene_files *files, char *err, size_t errlen);

/* Writes the scene to path atomically (no partial file on failure); its
 * images as references to files->images[i] (relative to path's
 * directory). RT_EUNSUPPORTED for a scene with images and no files. */
int rt_scene_json_dump(const rt_scene *s, const rt_scene_files *files, const char *path);

#endif
