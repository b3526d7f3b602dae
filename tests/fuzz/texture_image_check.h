/* texture_image_check.h - the properties the image-texture reader must keep
 * for any input at all, shared by the libFuzzer target and the replay. */
#ifndef RT_FUZZ_TEXTURE_IMAGE_CHECK_H
#define RT_FUZZ_TEXTURE_IMAGE_CHECK_H

#include <stddef.h>
#include <stdint.h>

/* Decodes data as an image file. NULL when every property holds: a known
 * status (never a crash), on failure an empty image, on success a size
 * within the limits whose every texel can be read, and the same texels from
 * a second decode. Otherwise a description of what broke. */
const char *fuzz_texture_image_check(const uint8_t *data, size_t size);

#endif
