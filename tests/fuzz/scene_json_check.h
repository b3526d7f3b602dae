/* scene_json_check.h - the properties the scene-file loader must keep for
 * any input at all, shared by the libFuzzer target and the corpus replay. */
#ifndef RT_FUZZ_SCENE_JSON_CHECK_H
#define RT_FUZZ_SCENE_JSON_CHECK_H

#include <stddef.h>
#include <stdint.h>

/* Parses data as a scene file. NULL when every property holds: a status
 * code (never a crash), on failure one message line naming the file and an
 * empty scene, on success dump -> load -> dump byte-identical and the same
 * scene. Otherwise a description of what broke. */
const char *fuzz_scene_json_check(const uint8_t *data, size_t size);

#endif
