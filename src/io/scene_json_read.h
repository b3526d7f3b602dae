/* scene_json_read.h - what the scene-file readers (scene_json.c: the file,
 * camera, tables; scene_json_object.c: materials, spheres;
 * scene_json_book2.c: textures, book 2's objects, media and instances)
 * share: the parse context, one-line
 * messages naming the field, and strict readers of JSON values. Private
 * to the rtscenejson library. */
#ifndef RT_SCENE_JSON_READ_H
#define RT_SCENE_JSON_READ_H

#include <cJSON.h>
#include <stddef.h>
#include <stdint.h>

#include "scene.h"
#include "scene_json.h"
#include "xform.h"

/* Coordinates and radii beyond this would overflow the squares taken by the
 * intersection and the BVH's boxes. */
#define RT_JSON_MAX_COORD 1e12
/* Instances may nest this deep (a group that instances itself stops here). */
#define RT_JSON_MAX_NESTING 16
/* Objects placed through instances, at most (a file of a few KiB must not
 * expand to millions by nesting). */
#define RT_JSON_MAX_PLACED 10000000u

typedef struct rt_json_ctx {
    const char *name; /* the file, as messages name it */
    char *err;
    size_t errlen;
    const char *dir;       /* image paths are relative to it; NULL: image textures refused */
    rt_scene_files *files; /* the images read, by index */
    const cJSON *root;
    int version;      /* the file's format version */
    uint32_t n_frames; /* the top level's frames (a sphere's "frame" indexes these) */
    uint32_t n_table; /* materials in the table (indices refer to these) */
    uint64_t placed;  /* objects placed through instances */
} rt_json_ctx;

/* Sets err to "<name>: <where>: <message>" and returns status. */
int rt_json_fail(rt_json_ctx *c, int status, const char *where, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* out = where.key */
void rt_json_join(char *out, size_t n, const char *where, const char *key);
/* A key or string from the file, fit to quote in a one-line message. */
void rt_json_quote(const char *key, char *out, size_t n);
/* Every key of obj one of allowed (NULL-terminated), each once. */
int rt_json_check_keys(rt_json_ctx *c, const cJSON *obj, const char *where, const char *const *allowed);
int rt_json_need_object(rt_json_ctx *c, const cJSON *item, const char *where);

/* A finite number in [lo, hi]; RT_JSON_OPEN_LO / _HI leave an end out. A
 * NULL item is "missing". */
enum { RT_JSON_CLOSED = 0, RT_JSON_OPEN_LO = 1, RT_JSON_OPEN_HI = 2 };
int rt_json_number(rt_json_ctx *c, const cJSON *item, const char *where, double lo, double hi, int open,
                   double *out);
int rt_json_vec3(rt_json_ctx *c, const cJSON *item, const char *where, double lo, double hi, rt_vec3 *out);
/* Members of obj: optional ones leave *out as it is when absent. */
int rt_json_opt_number(rt_json_ctx *c, const cJSON *obj, const char *where, const char *key, double lo, double hi,
                       int open, double *out);
int rt_json_req_number(rt_json_ctx *c, const cJSON *obj, const char *where, const char *key, double lo, double hi,
                       int open, double *out);
int rt_json_member_vec3(rt_json_ctx *c, const cJSON *obj, const char *where, const char *key, int required,
                        double lo, double hi, rt_vec3 *out);
/* A point (coordinates within RT_JSON_MAX_COORD), required. */
int rt_json_point(rt_json_ctx *c, const cJSON *obj, const char *where, const char *key, rt_vec3 *out);
/* Calls fn for each element of the array arr (named where.key), in order;
 * x and depth are passed on. Inside an instance (x), counts the objects
 * placed against RT_JSON_MAX_PLACED. */
typedef int (*rt_json_elem_fn)(rt_json_ctx *c, const cJSON *e, const char *w, const rt_xform *x, int depth,
                               rt_scene *s);
int rt_json_each(rt_json_ctx *c, const cJSON *arr, const char *where, const char *key, rt_json_elem_fn fn,
                 const rt_xform *x, int depth, rt_scene *s);
/* A status of an rt_scene_add_* call, with a message for the limits. */
int rt_json_add_status(rt_json_ctx *c, int st, const char *where);

/* Index i of the entry named by ref in array `table` (key table_key): a
 * number below `below`, or the string of an entry's "name". */
int rt_json_ref(rt_json_ctx *c, const cJSON *ref, const char *where, const char *table_key, uint32_t below,
                uint32_t *index);
/* A material reference: an index into the table, a name, or a material
 * object (added to the scene). */
int rt_json_material_ref(rt_json_ctx *c, const cJSON *ref, const char *where, rt_scene *s, uint32_t *index);
/* One material object. */
int rt_json_material(rt_json_ctx *c, const cJSON *obj, const char *w, rt_scene *s, rt_material *m);

/* A sphere (moving: a moving sphere) of obj, placed by x; a "frame" only
 * where x is NULL (the top level). */
int rt_json_sphere(rt_json_ctx *c, const cJSON *obj, const char *w, const rt_xform *x, int moving, rt_scene *s);

/* ---- scene_json_book2.c ---- */
/* The object lists of obj (spheres, moving_spheres, quads, boxes, media,
 * instances), each through x (NULL: none); depth: instances above. */
int rt_json_objects(rt_json_ctx *c, const cJSON *obj, const char *where, const rt_xform *x, int depth,
                    rt_scene *s);
/* The top level's textures (images read from c->dir) and frames. */
int rt_json_textures(rt_json_ctx *c, const cJSON *arr, rt_scene *s);
int rt_json_frames(rt_json_ctx *c, const cJSON *arr, rt_scene *s);

#endif
