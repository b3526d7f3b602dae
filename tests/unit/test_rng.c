/* test_rng.c - keyed streams: same key, same numbers, in any order; keys
 * differ -> streams differ; uniformity sanity. */
#include <stdlib.h>

#include "check.h"
#include "rng.h"

int main(void)
{
    /* Same (seed, pixel, sample) in any order gives the same numbers. */
    double first[64][4];
    for (int s = 0; s < 64; s++) {
        rt_rng r = rt_rng_for_sample(7, 1234, (uint64_t)s);
        for (int k = 0; k < 4; k++)
            first[s][k] = rt_rng_double(&r);
    }
    int same = 1;
    for (int s = 63; s >= 0; s--) {
        rt_rng r = rt_rng_for_sample(7, 1234, (uint64_t)s);
        for (int k = 0; k < 4; k++)
            same &= rt_rng_double(&r) == first[s][k];
    }
    CHECK(same);
    /* Neighbouring keys give unrelated streams. */
    rt_rng a = rt_rng_for_sample(7, 1234, 0), b = rt_rng_for_sample(7, 1235, 0), c = rt_rng_for_sample(8, 1234, 0);
    rt_rng d = rt_rng_for_sample(7, 1234, 1);
    uint64_t va = rt_rng_next(&a);
    CHECK(va != rt_rng_next(&b));
    CHECK(va != rt_rng_next(&c));
    CHECK(va != rt_rng_next(&d));
    /* Swapping pixel and sample must not alias. */
    rt_rng e = rt_rng_for_sample(7, 3, 5), f = rt_rng_for_sample(7, 5, 3);
    CHECK(rt_rng_next(&e) != rt_rng_next(&f));
    /* A known value pins the stream definition: changing the hash would
     * silently change every image. */
    rt_rng g = rt_rng_for_sample(0, 0, 0);
    CHECK_EQ_U64(rt_rng_next(&g), UINT64_C(0x0fed45340adc05d0));

    /* Uniformity: 64 bins over 1M draws from many keys, chi-square. */
    enum { BINS = 64, N = 1 << 20 };
    static long hist[BINS];
    double sum = 0, mn = 1, mx = 0;
    for (int i = 0; i < N; i++) {
        rt_rng r = rt_rng_for_sample(99, (uint64_t)i, (uint64_t)(i % 7));
        double u = rt_rng_double(&r);
        hist[(int)(u * BINS)]++;
        sum += u;
        mn = u < mn ? u : mn;
        mx = u > mx ? u : mx;
    }
    double expect = (double)N / BINS, chi2 = 0;
    for (int k = 0; k < BINS; k++)
        chi2 += (hist[k] - expect) * (hist[k] - expect) / expect;
    /* 63 degrees of freedom: p = 0.001 at ~103.4 */
    CHECK(chi2 < 103.4);
    if (chi2 >= 103.4)
        fprintf(stderr, "chi2 = %g\n", chi2);
    CHECK_NEAR(sum / N, 0.5, 0.002);
    CHECK(mn >= 0.0);
    CHECK(mx < 1.0);
    /* Scene stream is distinct from any sample stream of the same seed. */
    rt_rng s1 = rt_rng_for_stream(42, RT_STREAM_SCENE), s2 = rt_rng_for_sample(42, 0, 0);
    CHECK(rt_rng_next(&s1) != rt_rng_next(&s2));
    CHECK_DONE();
}
