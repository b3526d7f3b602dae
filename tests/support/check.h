/* check.h - value-printing assertions for the unit tests. A failed check
 * prints the expression, both values and the line, and the test goes on so
 * one run shows every failure; CHECK_DONE() prints the tally and returns the
 * exit status. */
#ifndef RT_TEST_CHECK_H
#define RT_TEST_CHECK_H

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static int check_pass, check_fail;

#define CHECK(cond)                                                                                                \
    do {                                                                                                           \
        if (cond) {                                                                                                \
            check_pass++;                                                                                          \
        } else {                                                                                                   \
            check_fail++;                                                                                          \
            fprintf(stderr, "%s:%d: CHECK(%s) failed\n", __FILE__, __LINE__, #cond);                               \
        }                                                                                                          \
    } while (0)

#define CHECK_EQ_INT(a, b)                                                                                         \
    do {                                                                                                           \
        long long va_ = (long long)(a), vb_ = (long long)(b);                                                      \
        if (va_ == vb_) {                                                                                          \
            check_pass++;                                                                                          \
        } else {                                                                                                   \
            check_fail++;                                                                                          \
            fprintf(stderr, "%s:%d: CHECK_EQ_INT(%s, %s) failed: %lld != %lld\n", __FILE__, __LINE__, #a, #b, va_, \
                    vb_);                                                                                          \
        }                                                                                                          \
    } while (0)

#define CHECK_EQ_U64(a, b)                                                                                         \
    do {                                                                                                           \
        uint64_t va_ = (uint64_t)(a), vb_ = (uint64_t)(b);                                                         \
        if (va_ == vb_) {                                                                                          \
            check_pass++;                                                                                          \
        } else {                                                                                                   \
            check_fail++;                                                                                          \
            fprintf(stderr, "%s:%d: CHECK_EQ_U64(%s, %s) failed: %016" PRIx64 " != %016" PRIx64 "\n", __FILE__,   \
                    __LINE__, #a, #b, va_, vb_);                                                                   \
        }                                                                                                          \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                                                      \
    do {                                                                                                           \
        double va_ = (double)(a), vb_ = (double)(b), vt_ = (double)(tol);                                          \
        if (fabs(va_ - vb_) <= vt_) {                                                                              \
            check_pass++;                                                                                          \
        } else {                                                                                                   \
            check_fail++;                                                                                          \
            fprintf(stderr, "%s:%d: CHECK_NEAR(%s, %s, %s) failed: %.17g vs %.17g (diff %.3g > %.3g)\n", __FILE__, \
                    __LINE__, #a, #b, #tol, va_, vb_, fabs(va_ - vb_), vt_);                                       \
        }                                                                                                          \
    } while (0)

#define CHECK_HAS(text, part)                                                                                      \
    do {                                                                                                           \
        const char *vt_ = (text), *vp_ = (part);                                                                   \
        if (strstr(vt_, vp_)) {                                                                                    \
            check_pass++;                                                                                          \
        } else {                                                                                                   \
            check_fail++;                                                                                          \
            fprintf(stderr, "%s:%d: CHECK_HAS(%s, %s) failed: '%s' lacks '%s'\n", __FILE__, __LINE__, #text, #part, \
                    vt_, vp_);                                                                                     \
        }                                                                                                          \
    } while (0)

#define CHECK_DONE()                                                                                               \
    do {                                                                                                           \
        printf("%d passed, %d failed\n", check_pass, check_fail);                                                  \
        return check_fail ? 1 : 0;                                                                                 \
    } while (0)

#endif
