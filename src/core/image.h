/* image.h - turning accumulated fixed-point sums into output pixels, and
 * fingerprinting them. No file formats here (see io/image_write.h): the core
 * library stays free of libpng. */
#ifndef RT_IMAGE_H
#define RT_IMAGE_H

#include <stddef.h>
#include <stdint.h>

#include "job.h"

/* 8-bit gamma-2 RGB as the book writes it: sqrt(sum / samples) clamped to
 * [0, 0.999], times 256, truncated. n = number of pixels. */
void rt_image_to_rgb8(const int64_t *acc, size_t n, uint32_t samples, uint8_t *rgb);
/* 16-bit big-endian-agnostic values (host order) with the same gamma and
 * clamp, scaled to 65536. */
void rt_image_to_rgb16(const int64_t *acc, size_t n, uint32_t samples, uint16_t *rgb);
/* Linear radiance (sum / samples) as float, unclamped, for PFM/EXR. */
void rt_image_to_linear(const int64_t *acc, size_t n, uint32_t samples, float *rgb);

/* The three values at offset `first` (the colour 0, lay.albedo,
 * lay.normal) of n pixels of lay.ch values each, as a buffer of 3 sums per
 * pixel of `samples` samples: copied, or with adaptive sampling (lay.count)
 * scaled from each pixel's own count to `samples` (rounded half away from
 * zero; a pixel with no samples is 0). The same sums give the same bits. */
void rt_image_extract(const int64_t *acc, size_t n, rt_layout lay, uint32_t first, uint32_t samples, int64_t *out);

/* 64-bit FNV-1a of bytes, printed as the run's image hash. */
uint64_t rt_image_hash(const uint8_t *bytes, size_t len);

#endif
