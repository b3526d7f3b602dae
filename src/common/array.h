/* array.h - growing a malloc'd array: the one place that doubles a
 * capacity, so every list in the project (scene, work units, pending
 * results, trace events) grows the same way and checks the same failure. */
#ifndef RT_ARRAY_H
#define RT_ARRAY_H

#include <stddef.h>
#include <stdlib.h>

#include "status.h"

/* Makes *p hold at least `need` elements of `elem` bytes; *cap counts
 * elements and at least doubles when it grows. On RT_ENOMEM *p and *cap are
 * unchanged. */
static inline int rt_array_reserve(void **p, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap)
        return RT_OK;
    size_t nc = *cap ? *cap : 16;
    while (nc < need)
        nc *= 2;
    if (nc > (size_t)-1 / elem)
        return RT_ENOMEM;
    void *q = realloc(*p, nc * elem);
    if (!q)
        return RT_ENOMEM;
    *p = q;
    *cap = nc;
    return RT_OK;
}

#endif
