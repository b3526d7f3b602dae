/* anim.h - a frame of an animation (issue 37): the camera and the interval
 * of the rays' time of frame `frame`, computed from its number alone on
 * every rank (nothing per frame is broadcast), so a frame renders to the
 * same bytes in a range or alone. A minimal version: the turntable and the
 * frame-shifted time; camera keyframes and --shutter come with the scene
 * side of issue 37. */
#ifndef RT_ANIM_H
#define RT_ANIM_H

#include <stdint.h>

#include "scene.h"

typedef struct rt_anim_opts {
    double turn_degrees;  /* --turntable DEGREES:FRAMES */
    uint32_t turn_frames; /* 0: no turntable */
    double shutter_open, shutter_close; /* --shutter, fractions of a frame */
    int shutter_set;      /* --shutter given */
} rt_anim_opts;

/* Frame `frame` of s under a: *cam the scene's camera, orbited by
 * rt_camera_orbit when a->turn_frames != 0, and [*t0, *t1) the rays' time
 * (frame 0 without a turntable: the scene's camera and [0, 1), to the bit).
 * A status: RT_EINVAL when the orbit fails. */
int rt_anim_frame(const rt_scene *s, const rt_anim_opts *a, uint32_t frame, rt_camera_desc *cam, double *t0,
                  double *t1);

#endif
