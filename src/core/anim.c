/* anim.c - a frame's camera and time interval (anim.h). */
#include "anim.h"

#include "camera.h"
#include "status.h"

int rt_anim_frame(const rt_scene *s, const rt_anim_opts *a, uint32_t frame, rt_camera_desc *cam, double *t0,
                  double *t1)
{
    *cam = s->camera;
    *t0 = (double)frame;
    *t1 = (double)frame + 1.0;
    return a && a->turn_frames ? rt_camera_orbit(cam, frame, a->turn_degrees, a->turn_frames) : RT_OK;
}
