/* scene_files.c - the list of files a scene's images came from (what a
 * dump refers to), in builds with and without scene files. */
#include "scene_json.h"

#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "status.h"

int rt_scene_files_add(rt_scene_files *f, const char *path)
{
    char *copy = malloc(strlen(path) + 1);
    if (!copy || rt_array_reserve((void **)&f->images, &f->cap, (size_t)f->n + 1, sizeof *f->images)) {
        free(copy);
        return RT_ENOMEM;
    }
    strcpy(copy, path);
    f->images[f->n++] = copy;
    return RT_OK;
}

void rt_scene_files_free(rt_scene_files *f)
{
    for (uint32_t i = 0; i < f->n; i++)
        free(f->images[i]);
    free(f->images);
    memset(f, 0, sizeof *f);
}
