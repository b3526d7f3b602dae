/* cli_frames.c - the options of a frame job (issue 37): --frames, --frame,
 * --turntable and --shutter, and the checks of its output patterns (every frame's
 * files creatable, no two patterns naming the same file). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "status.h"

/* Frames whose paths the collision check compares: enough for any pattern
 * whose numbers could meet (they differ in the last digits first). */
#define CHECK_FRAMES 2000u

int rt_cli_frames_option(const char *lng, const char *name, const char *val, rt_options *o, char *err, size_t errlen)
{
    const char *why = NULL;
    if (!strcmp(lng, "turntable")) {
        char *end;
        double deg = strtod(val, &end);
        uint64_t n = 0;
        if (end == val || *end != ':' || !isfinite(deg) || fabs(deg) > 1e6 ||
            rt_cli_parse_u64(end + 1, 1, RT_FRAMES_MAX, &n)) {
            snprintf(err, errlen, "%s: '%s' is not DEGREES:FRAMES (a number of degrees every FRAMES frames, FRAMES >= 1)",
                     name, val);
            return RT_EINVAL;
        }
        o->anim.turn_degrees = deg;
        o->anim.turn_frames = (uint32_t)n;
        return RT_OK;
    }
    if (!strcmp(lng, "shutter")) {
        if (rt_anim_parse_shutter(val, &o->anim)) {
            snprintf(err, errlen, "%s: '%s' is not OPEN,CLOSE with 0 <= OPEN <= CLOSE <= 1", name, val);
            return RT_EINVAL;
        }
        return RT_OK;
    }
    if (o->frame_job) {
        snprintf(err, errlen, "%s: give one of --frames and --frame, once", name);
        return RT_EINVAL;
    }
    /* --frame N is the range N-N: the same text, minus the range's forms */
    if ((!strcmp(lng, "frame") && strspn(val, "0123456789") != strlen(val)) ||
        rt_frames_parse(val, &o->frames, &why)) {
        snprintf(err, errlen, "%s: '%s': %s", name, val, why ? why : "not a frame number");
        return RT_EINVAL;
    }
    o->frame_job = 1;
    return RT_OK;
}

int rt_cli_frames_settle(const rt_options *o, char *err, size_t errlen)
{
    if (o->anim.turn_frames && !o->frame_job) {
        snprintf(err, errlen, "--turntable: give the frames to render (--frames A-B[:STEP] or --frame N)");
        return RT_EINVAL;
    }
    if (o->frame_job && o->passes > 1) {
        snprintf(err, errlen, "--passes: progressive previews are for one image, not a frame range");
        return RT_EINVAL;
    }
    return RT_OK;
}

int rt_cli_frames_paths(const rt_options *o, uint32_t frame, rt_options *fo, rt_frame_paths *p)
{
    *fo = *o;
    fo->frame = frame;
    const char *const pat[RT_FRAME_PATTERNS] = {o->output, o->spp_map, o->stats, o->trace};
    const char **dst[RT_FRAME_PATTERNS] = {&fo->output, &fo->spp_map, &fo->stats, &fo->trace};
    for (int i = 0; i < RT_FRAME_PATTERNS; i++) {
        if (!pat[i])
            continue;
        int st = rt_frames_path(pat[i], frame, p->path[i], sizeof p->path[i]);
        if (st)
            return st;
        *dst[i] = p->path[i];
    }
    return RT_OK;
}

static int cmp_str(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* No two files of the job the same: the patterns' files of (up to
 * CHECK_FRAMES) frames, the checkpoint and the done file. */
static int check_collisions(const rt_options *o, char *err, size_t errlen)
{
    const uint32_t n = rt_frames_count(&o->frames) < CHECK_FRAMES ? rt_frames_count(&o->frames) : CHECK_FRAMES;
    const size_t cap = (size_t)n * RT_FRAME_PATTERNS + 2;
    char **all = calloc(cap, sizeof *all);
    rt_frame_paths *p = malloc(sizeof *p);
    size_t k = 0;
    int st = all && p ? RT_OK : RT_ENOMEM;
    for (uint32_t i = 0; i < n && !st; i++) {
        rt_options fo;
        if ((st = rt_cli_frames_paths(o, rt_frames_at(&o->frames, i), &fo, p)) != RT_OK)
            break;
        const char *got[RT_FRAME_PATTERNS] = {fo.output, fo.spp_map, fo.stats, fo.trace};
        for (int j = 0; j < RT_FRAME_PATTERNS && !st; j++)
            if (got[j] && !(all[k++] = strdup(got[j])))
                st = RT_ENOMEM;
    }
    if (!st && o->checkpoint && !(all[k++] = strdup(o->checkpoint)))
        st = RT_ENOMEM;
    if (!st && o->done_file && !(all[k++] = strdup(o->done_file)))
        st = RT_ENOMEM;
    if (!st) {
        qsort(all, k, sizeof *all, cmp_str);
        for (size_t i = 1; i < k && !st; i++)
            if (!strcmp(all[i - 1], all[i])) {
                snprintf(err, errlen, "--frames: two of the job's files would be '%s' (give each pattern its own name)",
                         all[i]);
                st = RT_EINVAL;
            }
    } else if (st == RT_ENOMEM) {
        snprintf(err, errlen, "out of memory");
    } else {
        snprintf(err, errlen, "--output: a frame's file name is too long");
    }
    for (size_t i = 0; all && i < k; i++)
        free(all[i]);
    free(all);
    free(p);
    return st;
}

int rt_cli_frames_check(const rt_options *o, char *err, size_t errlen)
{
    const char *const pat[RT_FRAME_PATTERNS] = {o->output, o->spp_map, o->stats, o->trace};
    const char *const opt[RT_FRAME_PATTERNS] = {"--output", "--spp-map", "--stats", "--trace"};
    for (int i = 0; i < RT_FRAME_PATTERNS; i++) {
        const char *slash = pat[i] ? strrchr(pat[i], '/') : NULL;
        if (slash && memchr(pat[i], '#', (size_t)(slash - pat[i]))) {
            snprintf(err, errlen, "%s: '%s': '#' is for the frame number in the file name, not the directory", opt[i],
                     pat[i]);
            return RT_EINVAL;
        }
    }
    rt_frame_paths *p = malloc(sizeof *p);
    rt_options fo;
    int st = p ? rt_cli_frames_paths(o, o->frames.first, &fo, p) : RT_ENOMEM;
    if (st)
        snprintf(err, errlen, "%s", st == RT_ENOMEM ? "out of memory" : "--output: a frame's file name is too long");
    else
        st = rt_cli_check_output(&fo, err, errlen);
    if (!st && fo.stats)
        st = rt_cli_check_path("--stats", fo.stats, err, errlen);
    if (!st && fo.trace)
        st = rt_cli_check_path("--trace", fo.trace, err, errlen);
    free(p);
    return st ? st : check_collisions(o, err, errlen);
}
