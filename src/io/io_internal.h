/* io_internal.h - io's entry points that only its tests and the fuzzer
 * call: no other layer includes this header. */
#ifndef RT_IO_INTERNAL_H
#define RT_IO_INTERNAL_H

#include <stddef.h>

#include "scene.h"
#include "scene_json.h"

/* ---- scene_json.c ---- */
/* Parses len bytes of JSON text (no NUL terminator needed) into s. name is
 * the file name used in messages. On failure s is left empty, the status is
 * RT_EFORMAT (bad content), RT_EOVERFLOW (too many spheres) or RT_ENOMEM,
 * and err holds one line "<name>: <field>: <what is wrong>", e.g.
 * "scene.json: spheres[3].radius: expected a number". */
/* dir: the directory image paths are relative to; NULL refuses image
 * textures (RT_EFORMAT: the fuzzer reads no files). files: as
 * rt_scene_json_load's. */
int rt_scene_json_parse(rt_scene *s, const char *text, size_t len, const char *name, const char *dir,
                        rt_scene_files *files, char *err, size_t errlen);

/* The scene as JSON text; *text is malloc'd and NUL-terminated, *len
 * excludes the NUL. Every double is written with the fewest digits that
 * read back to the same bits. */
/* image_paths[i]: what the file says for image i (NULL when the scene has
 * no images; RT_EUNSUPPORTED when it has). */
int rt_scene_json_format(const rt_scene *s, const char *const *image_paths, char **text, size_t *len);

#endif
