/* hash.h - FNV-1a 64 over bytes: fingerprints scenes, checkpoints and the
 * output image (the "image hash" a run prints). */
#ifndef RT_HASH_H
#define RT_HASH_H

#include <stddef.h>
#include <stdint.h>

#define RT_HASH_INIT UINT64_C(0xcbf29ce484222325)

/* Continues hash h over len bytes (start from RT_HASH_INIT). */
uint64_t rt_hash_bytes(uint64_t h, const void *data, size_t len);

#endif
