/* mem.h - large zeroed buffers (framebuffers and their snapshots) with
 * their pages mapped up front.
 *
 * Touching a fresh page costs a page fault; on the project's VM that is
 * about 10 us a page, so adding the bands into a calloc'd 600x400
 * framebuffer (5.8 MB) spent 15 to 16 ms in faults, serially, in the middle
 * of the render. One mmap with MAP_POPULATE maps the same pages in 1.4 ms. Where
 * MAP_POPULATE does not exist this is calloc and free.
 *
 * Mapping up front is itself serial work: rank 0's framebuffer of
 * 1200x800 (23 MB) took about 7 ms to map before rank 0 could hand out its
 * first unit, while every other rank waited; the time grows with the
 * framebuffer (199 MB at 3840x2160). rt_mem_zeroed_early returns at once
 * and maps the pages from a thread of its own. */
#ifndef RT_MEM_H
#define RT_MEM_H

#include <pthread.h>
#include <stddef.h>

/* bytes of zeroes (NULL if out of memory); release with rt_mem_free and the
 * same size. */
void *rt_mem_zeroed(size_t bytes);
void rt_mem_free(void *p, size_t bytes);

/* rt_mem_zeroed, but the pages are mapped by a thread meanwhile, with
 * MADV_POPULATE_WRITE, which leaves the contents alone: the buffer may be
 * read and written at once (a page touched first is mapped then, as with
 * calloc). Where that does not exist, calloc's mapping page by page.
 * e->p is the buffer (NULL if out of memory); rt_mem_settle waits for the
 * thread (before rt_mem_free, or to time it). */
typedef struct rt_mem_early {
    void *p;
    size_t bytes;
    pthread_t thread;
    int running;
} rt_mem_early;
void rt_mem_zeroed_early(rt_mem_early *e, size_t bytes);
void rt_mem_settle(rt_mem_early *e);

/* Keeps blocks that malloc gives back (up to 32 MB each) in the heap for
 * the next allocations, instead of unmapping them so that the next one
 * faults its pages in again (glibc; elsewhere nothing). The start-up copies
 * a scene's texels from the decoder to the scene, to its bytes and back:
 * book2-final's start-up 44.9 -> 35.1 ms of CPU, 2,320 -> 1,643 page faults
 * (perf stat -r 5, a 1 x 1 image). Call it first. */
void rt_mem_keep_freed(void);

#endif
