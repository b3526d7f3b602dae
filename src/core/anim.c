/* anim.c - a frame's camera and shutter: keyframe interpolation, the
 * turntable's orbit, the default shutter (the one place it is decided). */
#include "anim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "camera.h"
#include "status.h"

static int finite3(rt_vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

/* a + (b - a) s: a itself at s = 0, whatever b is. */
static double lerp(double a, double b, double s) { return a + (b - a) * s; }
static rt_vec3 lerp3(rt_vec3 a, rt_vec3 b, double s)
{
    return rt_v3(lerp(a.x, b.x, s), lerp(a.y, b.y, s), lerp(a.z, b.z, s));
}

static void key_view(const rt_camera_key *k, rt_camera_desc *d)
{
    d->lookfrom = k->lookfrom;
    d->lookat = k->lookat;
    d->vup = k->vup;
    d->vfov_deg = k->vfov_deg;
    d->aperture = k->aperture;
    d->focus_dist = k->focus_dist;
}

void rt_anim_keys_at(const rt_scene *s, double frame, rt_camera_desc *d)
{
    const rt_camera_key *k = s->keys.items;
    const uint32_t n = s->keys.n;
    if (!n)
        return;
    if (!(frame > k[0].frame)) { /* before the first key, or at it */
        key_view(&k[0], d);
        return;
    }
    uint32_t i = 1; /* the first key after frame: k[i - 1].frame <= frame < k[i].frame */
    while (i < n && !(frame < k[i].frame))
        i++;
    if (i == n) { /* at the last key or after it */
        key_view(&k[n - 1], d);
        return;
    }
    const rt_camera_key *a = &k[i - 1], *b = &k[i];
    const double t = (frame - a->frame) / (b->frame - a->frame); /* [0, 1): exactly 0 at a key */
    d->lookfrom = lerp3(a->lookfrom, b->lookfrom, t);
    d->lookat = lerp3(a->lookat, b->lookat, t);
    d->vup = lerp3(a->vup, b->vup, t);
    d->vfov_deg = lerp(a->vfov_deg, b->vfov_deg, t);
    d->aperture = lerp(a->aperture, b->aperture, t);
    d->focus_dist = lerp(a->focus_dist, b->focus_dist, t);
}

int rt_anim_camera_animates(const rt_scene *s) { return s->keys.n > 0; }

static int usable(const rt_camera_desc *d)
{
    rt_camera probe;
    return rt_camera_init(&probe, d, 1.0) == RT_OK;
}

int rt_anim_add_key(rt_scene *s, const rt_camera_key *k)
{
    if (s->keys.n >= RT_SCENE_MAX_KEYS)
        return RT_EOVERFLOW;
    if (!(k->frame >= 0.0 && k->frame < 4294967296.0) || !finite3(k->lookfrom) || !finite3(k->lookat) ||
        !finite3(k->vup) || !isfinite(k->vfov_deg) || !isfinite(k->aperture) || !isfinite(k->focus_dist))
        return RT_EINVAL;
    if (s->keys.n && !(k->frame > s->keys.items[s->keys.n - 1].frame))
        return RT_EINVAL;
    rt_camera_desc d = s->camera;
    key_view(k, &d);
    if (!usable(&d))
        return RT_EINVAL;
    int st = rt_array_reserve((void **)&s->keys.items, &s->keys.cap, (size_t)s->keys.n + 1, sizeof *k);
    if (!st)
        s->keys.items[s->keys.n++] = *k;
    return st;
}

static int shutter_ok(double open, double close) { return open >= 0.0 && open <= close && close <= 1.0; }

int rt_anim_frame(const rt_scene *s, const rt_anim_opts *a, uint32_t frame, rt_camera_desc *cam, double *t0,
                  double *t1)
{
    *cam = s->camera;
    rt_anim_keys_at(s, (double)frame, cam);
    if (a && a->turn_frames && rt_camera_orbit(cam, frame, a->turn_degrees, a->turn_frames) != RT_OK)
        return RT_EINVAL;
    /* the default shutter: the book's [0, 1) where something moves */
    double open = 0.0, close = s->shapes.movers.n ? 1.0 : 0.0;
    if (a && a->shutter_set) {
        open = a->shutter_open;
        close = a->shutter_close;
        if (!shutter_ok(open, close))
            return RT_EINVAL;
    }
    *t0 = (double)frame + open;
    *t1 = (double)frame + close;
    return usable(cam) ? RT_OK : RT_EINVAL;
}

int rt_anim_span(const rt_scene *s, const rt_anim_opts *a, uint32_t first, uint32_t last, double *t_lo,
                 double *t_hi)
{
    rt_camera_desc cam;
    double t0, t1;
    if (last < first || rt_anim_frame(s, a, first, &cam, t_lo, &t1) || rt_anim_frame(s, a, last, &cam, &t0, t_hi))
        return RT_EINVAL;
    return RT_OK;
}

int rt_anim_parse_shutter(const char *text, rt_anim_opts *a)
{
    char *end;
    const double open = strtod(text, &end);
    if (end == text || *end != ',')
        return RT_EINVAL;
    const char *rest = end + 1;
    const double close = strtod(rest, &end);
    if (end == rest || *end || !shutter_ok(open, close))
        return RT_EINVAL;
    a->shutter_open = open;
    a->shutter_close = close;
    a->shutter_set = 1;
    return RT_OK;
}
