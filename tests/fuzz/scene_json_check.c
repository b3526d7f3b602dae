/* scene_json_check.c - see scene_json_check.h. */
#include "io_internal.h"
#include "core_internal.h"
#include "scene_json_check.h"

#include <stdlib.h>
#include <string.h>

#include "scene_json.h"
#include "status.h"

const char *fuzz_scene_json_check(const uint8_t *data, size_t size)
{
    rt_scene s;
    char err[512] = "";
    int st = rt_scene_json_parse(&s, (const char *)data, size, "fuzz.json", err, sizeof err);
    if (st != RT_OK) {
        if (st != RT_EFORMAT && st != RT_EOVERFLOW && st != RT_ENOMEM)
            return "unexpected status";
        if (strncmp(err, "fuzz.json: ", 11) != 0 || strchr(err, '\n') || strlen(err) < 14)
            return "error message does not name the file in one line";
        if (s.n_spheres || s.n_materials || s.spheres || s.materials)
            return "failed parse left a scene behind";
        return NULL;
    }
    const char *bad = NULL;
    char *t1 = NULL, *t2 = NULL;
    size_t n1, n2;
    rt_scene b;
    if (rt_scene_json_format(&s, &t1, &n1) != RT_OK) {
        bad = "format failed";
    } else if (rt_scene_json_parse(&b, t1, n1, "dump.json", err, sizeof err) != RT_OK) {
        bad = "a dump does not load";
    } else {
        if (rt_scene_json_format(&b, &t2, &n2) != RT_OK || n1 != n2 || memcmp(t1, t2, n1) != 0)
            bad = "dump -> load -> dump differs";
        else if (rt_scene_hash(&b) != rt_scene_hash(&s))
            bad = "a loaded dump is a different scene";
        rt_scene_free(&b);
    }
    free(t1);
    free(t2);
    rt_scene_free(&s);
    return bad;
}
