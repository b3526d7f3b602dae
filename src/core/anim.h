/* anim.h - a frame of a sequence: its camera (the scene's, its camera
 * keyframes interpolated at the frame, or the turntable's orbit) and the
 * interval of its rays' time (the shutter). Pure functions of the frame
 * number, computed on every rank with plain + - * / in double (the build
 * turns off FMA contraction), so a frame's bytes depend on its number
 * alone and are the same bits on every node. */
#ifndef RT_ANIM_H
#define RT_ANIM_H

#include <stdint.h>

#include "scene.h"

/* What the command line adds to the scene's animation. */
typedef struct rt_anim_opts {
    double turn_degrees;  /* --turntable DEGREES:FRAMES: the orbit every turn_frames frames */
    uint32_t turn_frames; /* 0: no turntable */
    double shutter_open, shutter_close; /* --shutter, fractions of a frame, 0 <= open <= close <= 1 */
    int shutter_set;      /* 0: the default shutter (rt_anim_frame) */
} rt_anim_opts;

/* Frame `frame`'s camera and the interval [*t0, *t1) its rays' time is
 * drawn from (t0 = t1: every ray at t0, no motion blur). The camera: the
 * scene's, or with keyframes the keys interpolated linearly at time
 * `frame` (held before the first key and after the last; pixels from the
 * scene's camera); then, with a turntable (a may ask for one), orbited by
 * rt_camera_orbit. The time: frame + the shutter, whose default is the
 * book's [0, 1) for scenes with moving spheres and [0, 0] otherwise. So
 * frame 0 of a scene without keys, turntable or --shutter has the scene's
 * camera and [0, 1) (book 2) to the bit. a may be NULL (no options).
 * RT_EINVAL for a shutter out of order or out of [0, 1], a bad turntable
 * or a degenerate camera (rt_camera_init refuses it). */
int rt_anim_frame(const rt_scene *s, const rt_anim_opts *a, uint32_t frame, rt_camera_desc *cam, double *t0,
                  double *t1);

/* The rays' times of frames first..last together, [*t_lo, *t_hi]: what
 * the accelerator must hold moving spheres for (rt_accel_new_span). The
 * closest hit does not depend on it (ties go to the lower item), so a
 * frame renders the same bytes in any range. RT_EINVAL as rt_anim_frame,
 * or for last < first. */
int rt_anim_span(const rt_scene *s, const rt_anim_opts *a, uint32_t first, uint32_t last, double *t_lo,
                 double *t_hi);

/* 1 when the scene's camera moves by itself (it has keyframes): a
 * turntable on top of it is refused. */
int rt_anim_camera_animates(const rt_scene *s);

/* Appends keyframe k after the scene's last one. RT_EINVAL for a
 * non-finite value, a frame not after the last key's (keys are sorted
 * and distinct), a frame outside [0, 2^32), or a degenerate camera;
 * RT_EOVERFLOW past RT_SCENE_MAX_KEYS; RT_ENOMEM. */
int rt_anim_add_key(rt_scene *s, const rt_camera_key *k);

/* The keyframes interpolated at time `frame` into d's view (d's pixels
 * are kept); d is left as it is when the scene has none. */
void rt_anim_keys_at(const rt_scene *s, double frame, rt_camera_desc *d);

/* Parses "OPEN,CLOSE" (fractions of a frame, 0 <= OPEN <= CLOSE <= 1)
 * into a's shutter: RT_OK, or RT_EINVAL. */
int rt_anim_parse_shutter(const char *text, rt_anim_opts *a);

#endif
