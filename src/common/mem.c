/* mem.c - see mem.h. */
#define _DEFAULT_SOURCE /* MAP_ANONYMOUS, MAP_POPULATE */
#include "mem.h"

#include <stdlib.h>

#if defined(__linux__)
#include <sys/mman.h>
#endif

/* Below this, malloc's own pool serves faster than a mapping of its own. */
#define MAPPED_MIN ((size_t)1 << 20)

void *rt_mem_zeroed(size_t bytes)
{
#if defined(__linux__) && defined(MAP_POPULATE)
    if (bytes >= MAPPED_MIN) {
        void *p = mmap(NULL, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_POPULATE, -1, 0);
        return p == MAP_FAILED ? NULL : p;
    }
#endif
    return calloc(bytes ? bytes : 1, 1);
}

void rt_mem_free(void *p, size_t bytes)
{
    if (!p)
        return;
#if defined(__linux__) && defined(MAP_POPULATE)
    if (bytes >= MAPPED_MIN) {
        munmap(p, bytes);
        return;
    }
#endif
    (void)bytes;
    free(p);
}
