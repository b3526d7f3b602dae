/* frames.c - frame ranges and output patterns. */
#include "frames.h"

#include <stdio.h>
#include <string.h>

#include "status.h"

/* A decimal number of at most 9 digits at *p; advances *p. */
static int number(const char **p, uint32_t *v)
{
    const char *s = *p;
    uint32_t x = 0;
    int digits = 0;
    while (*s >= '0' && *s <= '9') {
        if (++digits > 9)
            return 0;
        x = x * 10 + (uint32_t)(*s++ - '0');
    }
    *p = s;
    *v = x;
    return digits > 0;
}

int rt_frames_parse(const char *text, rt_frames *out, const char **why)
{
    const char *p = text ? text : "";
    uint32_t a, b, step = 1;
    *why = "not a frame range (A-B, A-B:STEP or N)";
    if (!number(&p, &a))
        return RT_EINVAL;
    b = a;
    if (*p == '-') {
        p++;
        if (!number(&p, &b))
            return RT_EINVAL;
        if (*p == ':') {
            p++;
            if (!number(&p, &step))
                return RT_EINVAL;
        }
    }
    if (*p)
        return RT_EINVAL;
    if (a > RT_FRAMES_MAX || b > RT_FRAMES_MAX || step > RT_FRAMES_MAX) {
        *why = "frame numbers go up to 999999999";
        return RT_EINVAL;
    }
    if (b < a) {
        *why = "the range is reversed (its last frame comes before its first)";
        return RT_EINVAL;
    }
    if (step == 0) {
        *why = "a step of 0";
        return RT_EINVAL;
    }
    *out = (rt_frames){.first = a, .last = a + (b - a) / step * step, .step = step};
    *why = NULL;
    return RT_OK;
}

uint32_t rt_frames_count(const rt_frames *f) { return (f->last - f->first) / f->step + 1; }

uint32_t rt_frames_at(const rt_frames *f, uint32_t i) { return f->first + i * f->step; }

/* Appends n bytes of s to out at *at (cap bytes in all, one kept for the
 * terminator); 0 when it does not fit. */
static int put(char *out, size_t cap, size_t *at, const char *s, size_t n)
{
    if (*at + n >= cap)
        return 0;
    memcpy(out + *at, s, n);
    *at += n;
    return 1;
}

static int put_number(char *out, size_t cap, size_t *at, uint32_t frame, int width)
{
    char num[32];
    int n = snprintf(num, sizeof num, "%0*u", width, (unsigned)frame);
    return n > 0 && put(out, cap, at, num, (size_t)n);
}

int rt_frames_path(const char *pattern, uint32_t frame, char *out, size_t n)
{
    const char *slash = strrchr(pattern, '/');
    const char *name = slash ? slash + 1 : pattern;
    if (memchr(pattern, '#', (size_t)(name - pattern)))
        return RT_EINVAL;
    size_t at = 0;
    if (!strchr(name, '#')) {
        const char *dot = strrchr(name, '.');
        size_t stem = dot && dot != name ? (size_t)(dot - pattern) : strlen(pattern);
        if (!put(out, n, &at, pattern, stem) || !put_number(out, n, &at, frame, RT_FRAMES_PAD) ||
            !put(out, n, &at, pattern + stem, strlen(pattern + stem)))
            return RT_EOVERFLOW;
    } else {
        for (const char *p = pattern; *p;) {
            size_t run = strspn(p, "#");
            if (run > 64 || (run ? !put_number(out, n, &at, frame, (int)run) : !put(out, n, &at, p, 1)))
                return RT_EOVERFLOW;
            p += run ? run : 1;
        }
    }
    out[at] = '\0';
    return RT_OK;
}
