/* test_frames.c - frame ranges (--frames, --frame) and output patterns. */
#include <string.h>

#include "check.h"
#include "frames.h"
#include "status.h"

static void check_range(const char *text, uint32_t first, uint32_t last, uint32_t step, uint32_t count)
{
    rt_frames f = {0};
    const char *why = "unset";
    CHECK_EQ_INT(rt_frames_parse(text, &f, &why), RT_OK);
    CHECK(why == NULL);
    CHECK_EQ_INT(f.first, first);
    CHECK_EQ_INT(f.last, last);
    CHECK_EQ_INT(f.step, step);
    CHECK_EQ_INT(rt_frames_count(&f), count);
    CHECK_EQ_INT(rt_frames_at(&f, count - 1), last);
}

static void test_ranges(void)
{
    check_range("1-250", 1, 250, 1, 250);
    check_range("7", 7, 7, 1, 1);
    check_range("0-10:5", 0, 10, 5, 3);
    check_range("1-10:4", 1, 9, 4, 3); /* the step never passes B */
    check_range("3-3:100", 3, 3, 100, 1);
    check_range("0-999999999", 0, 999999999, 1, 1000000000u);
}

static void check_refused(const char *text, const char *why_part)
{
    rt_frames f = {.first = 11, .last = 12, .step = 1};
    const char *why = NULL;
    CHECK_EQ_INT(rt_frames_parse(text, &f, &why), RT_EINVAL);
    CHECK(why && strstr(why, why_part));
    if (!why || !strstr(why, why_part))
        fprintf(stderr, "  '%s': why = '%s', wanted '%s'\n", text, why ? why : "(null)", why_part);
    CHECK_EQ_INT(f.first, 11); /* untouched */
}

static void test_refused(void)
{
    check_refused("10-1", "reversed");
    check_refused("1-10:0", "step of 0");
    check_refused("", "not a frame range");
    check_refused("-", "not a frame range");
    check_refused("5-", "not a frame range");
    check_refused("-5", "not a frame range");
    check_refused("1-2:", "not a frame range");
    check_refused("1-2:3:4", "not a frame range");
    check_refused("1..5", "not a frame range");
    check_refused(" 1-5", "not a frame range");
    check_refused("1-5 ", "not a frame range");
    check_refused("+1-5", "not a frame range");
    check_refused("1-1000000000", "not a frame range"); /* ten digits */
    check_refused("0-4294967297", "not a frame range"); /* would wrap in 32 bits */
}

static void check_path(const char *pattern, uint32_t frame, const char *want)
{
    char out[128];
    CHECK_EQ_INT(rt_frames_path(pattern, frame, out, sizeof out), RT_OK);
    CHECK(strcmp(out, want) == 0);
    if (strcmp(out, want))
        fprintf(stderr, "  pattern '%s' frame %u: '%s', wanted '%s'\n", pattern, (unsigned)frame, out, want);
}

static void test_paths(void)
{
    check_path("turn_####.png", 7, "turn_0007.png");
    check_path("turn_#.png", 12, "turn_12.png"); /* wider numbers keep every digit */
    check_path("a#b##.exr", 3, "a3b03.exr");
    check_path("out/turn.png", 42, "out/turn0042.png");
    check_path("dir.v2/turn", 42, "dir.v2/turn0042");
    check_path("a.b.png", 1, "a.b0001.png");
    check_path(".png", 5, ".png0005");
    check_path("frames/f_######", 123456789, "frames/f_123456789");
    char small[12];
    CHECK_EQ_INT(rt_frames_path("turn_####.png", 7, small, sizeof small), RT_EOVERFLOW);
    CHECK_EQ_INT(rt_frames_path("turn_####.pn", 7, small, sizeof small), RT_EOVERFLOW); /* 12 + NUL */
    CHECK_EQ_INT(rt_frames_path("turn_###.pn", 7, small, sizeof small), RT_OK);
    CHECK_EQ_INT(rt_frames_path("shot##/f.png", 7, small, sizeof small), RT_EINVAL);
}

int main(void)
{
    test_ranges();
    test_refused();
    test_paths();
    CHECK_DONE();
}
