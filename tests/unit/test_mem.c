/* test_mem.c - rt_mem_zeroed gives writable zeroes of every size, and (on
 * Linux) a large buffer's pages are all mapped before anything touches them,
 * which is what the module is for. */
#define _DEFAULT_SOURCE /* mincore */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "check.h"
#include "mem.h"

int main(void)
{
    const size_t sizes[] = {0, 1, 4096, (1u << 20) - 8, 1u << 20, 600 * 400 * 3 * 8};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        size_t n = sizes[k];
        unsigned char *p = rt_mem_zeroed(n);
        CHECK(p != NULL);
        if (!p)
            continue;
#if defined(__linux__)
        if (n >= (1u << 20)) { /* resident before the first touch */
            size_t page = (size_t)sysconf(_SC_PAGESIZE), pages = (n + page - 1) / page, resident = 0;
            unsigned char *vec = malloc(pages);
            CHECK(vec && mincore(p, n, vec) == 0);
            for (size_t i = 0; vec && i < pages; i++)
                resident += vec[i] & 1;
            CHECK_EQ_U64(resident, pages);
            free(vec);
        }
#endif
        size_t nonzero = 0;
        for (size_t i = 0; i < n; i++)
            nonzero += p[i] != 0;
        CHECK_EQ_U64(nonzero, 0);
        memset(p, 0xa5, n);
        uint64_t sum = 0;
        for (size_t i = 0; i < n; i++)
            sum += p[i];
        CHECK_EQ_U64(sum, (uint64_t)n * 0xa5);
        rt_mem_free(p, n);
    }
    rt_mem_free(NULL, 1u << 20); /* like free(NULL) */
    CHECK_DONE();
}
