/* scene_json_check.c - see scene_json_check.h. */
#include "io_internal.h"
#include "core_internal.h"
#include "scene_json_check.h"

#include <stdlib.h>
#include <string.h>

#include "scene_json.h"
#include "status.h"

/* What every loaded scene satisfies: its byte form decodes (every index
 * in range, every value finite: rt_scene_deserialize checks them) to the
 * same scene; quads have area; media are isotropic inside closed hulls. */
static const char *loaded_scene_ok(const rt_scene *s)
{
    uint8_t *buf;
    size_t len;
    rt_scene back;
    if (rt_scene_serialize(s, &buf, &len) != RT_OK)
        return "a loaded scene does not serialize";
    int st = rt_scene_deserialize(&back, buf, len);
    free(buf);
    if (st != RT_OK)
        return "a loaded scene's bytes do not decode";
    const int same = rt_scene_hash(&back) == rt_scene_hash(s);
    rt_scene_free(&back);
    if (!same)
        return "a loaded scene's bytes decode to another scene";
    for (uint32_t i = 0; i < s->shapes.quads.n; i++) {
        const rt_quad *q = &s->shapes.quads.items[i];
        if (!(rt_v3_len2(rt_v3_cross(q->u, q->v)) > 0))
            return "a quad without area";
    }
    for (uint32_t i = 0; i < s->media.media.n; i++) {
        const rt_medium *m = &s->media.media.items[i];
        if (s->materials[m->material].kind != RT_MAT_ISOTROPIC || !(m->density > 0))
            return "a medium that is not isotropic or has no density";
        if (m->shape == RT_MEDIUM_HULL && rt_scene_hull_check(s->media.hull.items + m->first, m->count) != RT_OK)
            return "a medium's hull is open";
    }
    return NULL;
}

const char *fuzz_scene_json_check(const uint8_t *data, size_t size)
{
    rt_scene s;
    char err[512] = "";
    int st = rt_scene_json_parse(&s, (const char *)data, size, "fuzz.json", NULL, NULL, err, sizeof err);
    if (st != RT_OK) {
        if (st != RT_EFORMAT && st != RT_EOVERFLOW && st != RT_ENOMEM)
            return "unexpected status";
        if (strncmp(err, "fuzz.json: ", 11) != 0 || strchr(err, '\n') || strlen(err) < 14)
            return "error message does not name the file in one line";
        if (s.n_spheres || s.n_materials || s.spheres || s.materials || s.shapes.quads.n || s.media.media.n ||
            s.tex.textures.n)
            return "failed parse left a scene behind";
        return NULL;
    }
    const char *bad = loaded_scene_ok(&s);
    char *t1 = NULL, *t2 = NULL;
    size_t n1, n2;
    rt_scene b;
    if (bad) {
        /* reported below */
    } else if (rt_scene_json_format(&s, NULL, &t1, &n1) != RT_OK) {
        bad = "format failed";
    } else if (rt_scene_json_parse(&b, t1, n1, "dump.json", NULL, NULL, err, sizeof err) != RT_OK) {
        bad = "a dump does not load";
    } else {
        if (rt_scene_json_format(&b, NULL, &t2, &n2) != RT_OK || n1 != n2 || memcmp(t1, t2, n1) != 0)
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
