/* frames.h - a job's frames (issue 37, being built): the range that
 * --frames A-B[:STEP] and --frame N give, and each frame's output file from
 * the -o pattern. Frames are numbers 0..RT_FRAMES_MAX. */
#ifndef RT_FRAMES_H
#define RT_FRAMES_H

#include <stddef.h>
#include <stdint.h>

#define RT_FRAMES_MAX 999999999u /* nine digits */
#define RT_FRAMES_PAD 4          /* digits of the number inserted when the pattern has no '#' */

typedef struct rt_frames {
    uint32_t first, last, step; /* first <= last, step >= 1; last is a frame of the range */
} rt_frames;

/* Parses "A-B", "A-B:STEP" or "N" (one frame). RT_EINVAL with *why set (a
 * phrase for the caller's message) for text that is not a range, a
 * reversed or empty range, a step of 0 or a number past RT_FRAMES_MAX.
 * last is rounded down to the last frame the step reaches. */
int rt_frames_parse(const char *text, rt_frames *out, const char **why);

/* How many frames, and the i-th (i < count). */
uint32_t rt_frames_count(const rt_frames *f);
uint32_t rt_frames_at(const rt_frames *f, uint32_t i);

/* The output file of frame `frame`: every run of '#' in the pattern's file
 * name becomes the number zero-padded to the run's length (wider numbers
 * keep every digit); without '#', the number padded to RT_FRAMES_PAD goes
 * before the extension (or at the end without one). RT_EINVAL for '#' in
 * the directory part, RT_EOVERFLOW when out (n bytes) is too small. */
int rt_frames_path(const char *pattern, uint32_t frame, char *out, size_t n);

#endif
