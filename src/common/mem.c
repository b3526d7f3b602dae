/* mem.c - see mem.h. */
#define _DEFAULT_SOURCE /* MAP_ANONYMOUS, MAP_POPULATE */
#include "mem.h"

#include <stdlib.h>

#if defined(__linux__)
#include <sys/mman.h>
#endif
#if defined(__GLIBC__)
#include <malloc.h>
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

#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
static void *populate(void *arg)
{
    rt_mem_early *e = arg;
    (void)madvise(e->p, e->bytes, MADV_POPULATE_WRITE); /* EINVAL before Linux 5.14: pages fault in as used */
    return NULL;
}
#endif

void rt_mem_zeroed_early(rt_mem_early *e, size_t bytes)
{
    e->bytes = bytes;
    e->running = 0;
#if defined(__linux__) && defined(MAP_POPULATE) && defined(MADV_POPULATE_WRITE)
    if (bytes >= MAPPED_MIN) {
        void *p = mmap(NULL, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        e->p = p == MAP_FAILED ? NULL : p;
        e->running = e->p && pthread_create(&e->thread, NULL, populate, e) == 0;
        return;
    }
#endif
    e->p = rt_mem_zeroed(bytes);
}

void rt_mem_settle(rt_mem_early *e)
{
    if (e->running)
        pthread_join(e->thread, NULL);
    e->running = 0;
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

void rt_mem_keep_freed(void)
{
#if defined(__GLIBC__) && defined(M_MMAP_THRESHOLD) && defined(M_TRIM_THRESHOLD)
    mallopt(M_MMAP_THRESHOLD, 32 << 20); /* glibc's largest on 64-bit hosts */
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
#endif
}
