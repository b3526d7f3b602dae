/* sampler.c - the tables of a Sobol pair's point (sampler.h,
 * rt_sampler_point and rt_sampler_pair0), built by the compiler from the
 * pair's generator matrices. */
#include "sampler.h"

/* Positions m of a 32-bit fraction's bits counted from its lowest (as in
 * rt_sampler_sobol1) whose bits are a superset of p's: where bit p of v
 * lands in rt_sampler_sobol1(v). */
#define SUPERSET(p)                                                                                                    \
    (((p) & 1 ? 0xaaaaaaaau : ~0u) & ((p) & 2 ? 0xccccccccu : ~0u) & ((p) & 4 ? 0xf0f0f0f0u : ~0u) &                  \
     ((p) & 8 ? 0xff00ff00u : ~0u) & ((p) & 16 ? 0xffff0000u : ~0u))
/* The point (unshifted) whose first coordinate has only bit p set. */
#define COLUMN(p) ((UINT64_C(1) << (32 + (p))) | SUPERSET(p))
/* By the index (rt_sampler_pair0): its bit j is bit 31 - j of the first
 * coordinate. By the first coordinate (rt_sampler_point): its bits. */
#define TERM(k, b, i) ((b) >> (i) & 1 ? COLUMN(BIT(8 * (k) + (i))) : 0)
#define ENTRY(k, b)                                                                                                    \
    (TERM(k, b, 0) ^ TERM(k, b, 1) ^ TERM(k, b, 2) ^ TERM(k, b, 3) ^ TERM(k, b, 4) ^ TERM(k, b, 5) ^ TERM(k, b, 6) ^ \
     TERM(k, b, 7))
#define E4(k, b) ENTRY(k, b), ENTRY(k, (b) + 1), ENTRY(k, (b) + 2), ENTRY(k, (b) + 3)
#define E16(k, b) E4(k, b), E4(k, (b) + 4), E4(k, (b) + 8), E4(k, (b) + 12)
#define E64(k, b) E16(k, b), E16(k, (b) + 16), E16(k, (b) + 32), E16(k, (b) + 48)
#define E256(k) {E64(k, 0), E64(k, 64), E64(k, 128), E64(k, 192)}

#define BIT(j) (31 - (j))
const uint64_t rt_sampler_pair0_table[4][256] = {E256(0), E256(1), E256(2), E256(3)};
#undef BIT
#define BIT(j) (j)
const uint64_t rt_sampler_point_table[4][256] = {E256(0), E256(1), E256(2), E256(3)};
