/* scene_json_read.c - the scene-file readers' shared parts: one-line
 * messages naming the field, strict readers of numbers and vectors, and
 * references into the materials and textures tables. */
#include "scene_json_read.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "status.h"

int rt_json_fail(rt_json_ctx *c, int status, const char *where, const char *fmt, ...)
{
    char msg[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (c->errlen)
        snprintf(c->err, c->errlen, "%s: %s%s%s", c->name, where, *where ? ": " : "", msg);
    return status;
}

void rt_json_quote(const char *key, char *out, size_t n)
{
    size_t j = 0;
    for (size_t i = 0; key[i] && j + 4 < n; i++) {
        if (i == 40) {
            out[j++] = '.';
            out[j++] = '.';
            out[j++] = '.';
            break;
        }
        unsigned char ch = (unsigned char)key[i];
        out[j++] = ch >= 0x20 && ch < 0x7f ? (char)ch : '?';
    }
    out[j] = 0;
}

void rt_json_join(char *out, size_t n, const char *where, const char *key)
{
    snprintf(out, n, "%s%s%s", where, *where ? "." : "", key);
}

int rt_json_check_keys(rt_json_ctx *c, const cJSON *obj, const char *where, const char *const *allowed)
{
    if (!cJSON_IsObject(obj)) /* its callers check first; an array's items have no names */
        return rt_json_need_object(c, obj, where);
    const cJSON *item;
    cJSON_ArrayForEach(item, obj)
    {
        char q[48], at[200];
        rt_json_quote(item->string ? item->string : "", q, sizeof q);
        rt_json_join(at, sizeof at, where, q);
        int known = 0;
        for (const char *const *a = allowed; *a; a++)
            known |= !strcmp(item->string, *a);
        if (!known) {
            char list[200] = "";
            for (const char *const *a = allowed; *a; a++)
                snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", a == allowed ? "" : ", ", *a);
            return rt_json_fail(c, RT_EFORMAT, at, "unknown field (expected one of: %s)", list);
        }
        for (const cJSON *prev = obj->child; prev != item; prev = prev->next)
            if (!strcmp(prev->string, item->string))
                return rt_json_fail(c, RT_EFORMAT, at, "duplicate field");
    }
    return RT_OK;
}

int rt_json_need_object(rt_json_ctx *c, const cJSON *item, const char *where)
{
    if (!item)
        return rt_json_fail(c, RT_EFORMAT, where, "missing");
    return cJSON_IsObject(item) ? RT_OK : rt_json_fail(c, RT_EFORMAT, where, "expected an object");
}

int rt_json_number(rt_json_ctx *c, const cJSON *item, const char *where, double lo, double hi, int open,
                   double *out)
{
    if (!item)
        return rt_json_fail(c, RT_EFORMAT, where, "missing");
    if (!cJSON_IsNumber(item))
        return rt_json_fail(c, RT_EFORMAT, where, "expected a number");
    double v = item->valuedouble;
    if (!isfinite(v))
        return rt_json_fail(c, RT_EFORMAT, where, "expected a finite number");
    if (!(open & RT_JSON_OPEN_LO ? v > lo : v >= lo) || !(open & RT_JSON_OPEN_HI ? v < hi : v <= hi))
        return rt_json_fail(c, RT_EFORMAT, where, "%.17g is out of range %c%g, %g%c", v,
                            open & RT_JSON_OPEN_LO ? '(' : '[', lo, hi, open & RT_JSON_OPEN_HI ? ')' : ']');
    *out = v;
    return RT_OK;
}

int rt_json_vec3(rt_json_ctx *c, const cJSON *item, const char *where, double lo, double hi, rt_vec3 *out)
{
    if (!item)
        return rt_json_fail(c, RT_EFORMAT, where, "missing");
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 3)
        return rt_json_fail(c, RT_EFORMAT, where, "expected an array of 3 numbers");
    double v[3];
    int i = 0;
    const cJSON *e;
    cJSON_ArrayForEach(e, item)
    {
        char at[220];
        snprintf(at, sizeof at, "%s[%d]", where, i);
        int st = rt_json_number(c, e, at, lo, hi, RT_JSON_CLOSED, &v[i]);
        if (st)
            return st;
        i++;
    }
    *out = rt_v3(v[0], v[1], v[2]);
    return RT_OK;
}

int rt_json_opt_number(rt_json_ctx *c, const cJSON *obj, const char *where, const char *key, double lo, double hi,
                       int open, double *out)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
    char at[200];
    rt_json_join(at, sizeof at, where, key);
    return item ? rt_json_number(c, item, at, lo, hi, open, out) : RT_OK;
}

int rt_json_req_number(rt_json_ctx *c, const cJSON *obj, const char *where, const char *key, double lo, double hi,
                       int open, double *out)
{
    char at[200];
    rt_json_join(at, sizeof at, where, key);
    return rt_json_number(c, cJSON_GetObjectItemCaseSensitive(obj, key), at, lo, hi, open, out);
}

int rt_json_member_vec3(rt_json_ctx *c, const cJSON *obj, const char *where, const char *key, int required,
                        double lo, double hi, rt_vec3 *out)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
    char at[200];
    rt_json_join(at, sizeof at, where, key);
    return item || required ? rt_json_vec3(c, item, at, lo, hi, out) : RT_OK;
}

int rt_json_point(rt_json_ctx *c, const cJSON *obj, const char *where, const char *key, rt_vec3 *out)
{
    return rt_json_member_vec3(c, obj, where, key, 1, -RT_JSON_MAX_COORD, RT_JSON_MAX_COORD, out);
}

int rt_json_add_status(rt_json_ctx *c, int st, const char *where)
{
    if (st == RT_EOVERFLOW)
        return rt_json_fail(c, st, where, "more than %u entries", RT_SCENE_MAX_SPHERES);
    if (st == RT_EINVAL) /* the loader checks first: left for what it does not foresee */
        return rt_json_fail(c, RT_EFORMAT, where, "not a valid object");
    return st == RT_ENOMEM ? rt_json_fail(c, st, where, "out of memory") : st;
}

int rt_json_ref(rt_json_ctx *c, const cJSON *ref, const char *where, const char *table_key, uint32_t below,
                uint32_t *index)
{
    if (!ref)
        return rt_json_fail(c, RT_EFORMAT, where, "missing");
    if (cJSON_IsNumber(ref)) {
        double v = ref->valuedouble;
        if (!(v >= 0 && v < (double)below && v == floor(v))) {
            if (below == 0)
                return rt_json_fail(c, RT_EFORMAT, where, "%.17g is not an index into %s (there are none)", v,
                                    table_key);
            return rt_json_fail(c, RT_EFORMAT, where, "%.17g is not an index into %s (0 to %u)", v, table_key,
                                below - 1);
        }
        *index = (uint32_t)v;
        return RT_OK;
    }
    if (!cJSON_IsString(ref))
        return rt_json_fail(c, RT_EFORMAT, where, "expected an index into %s or a name", table_key);
    const cJSON *table = cJSON_GetObjectItemCaseSensitive(c->root, table_key), *e;
    uint32_t i = 0;
    cJSON_ArrayForEach(e, table)
    {
        if (i >= below)
            break;
        const cJSON *name = cJSON_GetObjectItemCaseSensitive(e, "name");
        if (cJSON_IsString(name) && !strcmp(name->valuestring, ref->valuestring)) {
            *index = i;
            return RT_OK;
        }
        i++;
    }
    char q[48];
    rt_json_quote(ref->valuestring, q, sizeof q);
    return rt_json_fail(c, RT_EFORMAT, where, "no %s named '%s'%s", table_key, q,
                        below < (uint32_t)cJSON_GetArraySize(table) ? " before this entry" : "");
}

/* Calls fn for each element of arr (key, under where). */
int rt_json_each(rt_json_ctx *c, const cJSON *arr, const char *where, const char *key, rt_json_elem_fn fn, const rt_xform *x,
                int depth, rt_scene *s)
{
    char at[200];
    rt_json_join(at, sizeof at, where, key);
    if (!cJSON_IsArray(arr))
        return rt_json_fail(c, RT_EFORMAT, at, "expected an array");
    const cJSON *e;
    uint32_t i = 0;
    cJSON_ArrayForEach(e, arr)
    {
        char w[220];
        snprintf(w, sizeof w, "%s[%u]", at, i++);
        if (x && ++c->placed > RT_JSON_MAX_PLACED)
            return rt_json_fail(c, RT_EOVERFLOW, w, "instances place more than %u objects", RT_JSON_MAX_PLACED);
        int st = fn(c, e, w, x, depth, s);
        if (st)
            return st;
    }
    return RT_OK;
}
