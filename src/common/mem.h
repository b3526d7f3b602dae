/* mem.h - large zeroed buffers (framebuffers and their snapshots) with
 * their pages mapped up front.
 *
 * Touching a fresh page costs a page fault; on the project's VM that is
 * about 10 us a page, so adding the bands into a calloc'd 600x400
 * framebuffer (5.8 MB) spent 15 to 16 ms in faults, serially, in the middle
 * of the render. One mmap with MAP_POPULATE maps the same pages in 1.4 ms. Where
 * MAP_POPULATE does not exist this is calloc and free. */
#ifndef RT_MEM_H
#define RT_MEM_H

#include <stddef.h>

/* bytes of zeroes (NULL if out of memory); release with rt_mem_free and the
 * same size. */
void *rt_mem_zeroed(size_t bytes);
void rt_mem_free(void *p, size_t bytes);

#endif
