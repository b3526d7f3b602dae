/* scene_json.h - scene files: the JSON scene format (camera, background,
 * materials, spheres; see docs/SCENES_AND_FORMATS.md), read with cJSON and
 * written back so that dump -> load -> dump is byte-identical and a loaded
 * dump serializes to the very bytes of the scene it was dumped from.
 * Lives in its own library (rtscenejson) so the render core never links
 * cJSON. */
#ifndef RT_SCENE_JSON_H
#define RT_SCENE_JSON_H

#include <stddef.h>

#include "scene.h"

/* Format version written by the dumper; a file may name it ("version": 1). */
#define RT_SCENE_JSON_VERSION 1
/* Largest scene file read: a dump takes about 200 bytes per sphere, so
 * about five million spheres (a --grid 1000 dump is 801 MB). */
#define RT_SCENE_JSON_MAX_BYTES (1024u << 20)

/* Reads and parses the file at path (messages name it as given). RT_EIO
 * when it cannot be read. */
int rt_scene_json_load(rt_scene *s, const char *path, char *err, size_t errlen);

/* Writes the scene to path atomically (no partial file on failure). */
int rt_scene_json_dump(const rt_scene *s, const char *path);

#endif
