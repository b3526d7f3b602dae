/* scene_json_none.c - the scene-file functions of a build without cJSON:
 * they only say so (the option parser refuses scene files first). */
#include "scene_json.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "status.h"

int rt_scene_json_load(rt_scene *s, const char *path, rt_scene_files *files, char *err, size_t errlen)
{
    (void)s;
    (void)files;
    snprintf(err, errlen, "%s: this build of rt-mpi reads no scene files (built without cJSON)", path);
    return RT_EUNSUPPORTED;
}

int rt_scene_json_dump(const rt_scene *s, const rt_scene_files *files, const char *path)
{
    (void)s;
    (void)files;
    (void)path;
    return RT_EUNSUPPORTED;
}
