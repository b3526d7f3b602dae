/* test_sample.c - the libm-free cosine and sine against libm over the whole
 * turn (quarter-turn boundaries included), and the direct unit-vector
 * sampler: unit length, z strictly inside (-1, 1), and first and second
 * moments of a uniform direction. The law of the diffuse bounce built on it
 * is tested by chi-square in test_material.c. */
#include <stdint.h>

#include "check.h"
#include "rng.h"
#include "sample.h"

static void check_cos_sin(void)
{
    double worst = 0;
    uint32_t worst_q = 0;
    rt_rng rng = rt_rng_for_stream(7, RT_STREAM_TEST);
    /* every quarter-turn boundary and its neighbours, then random angles */
    uint32_t edges[] = {0, 1, 0x1fffffff, 0x20000000, 0x20000001, 0x3fffffff, 0x40000000, 0x5fffffff,
                        0x60000000, 0x80000000, 0x9fffffff, 0xa0000000, 0xc0000000, 0xdfffffff,
                        0xe0000000, 0xe0000001, 0xffffffff};
    for (long i = 0; i < 200000 + (long)(sizeof edges / sizeof edges[0]); i++) {
        uint32_t q = i < (long)(sizeof edges / sizeof edges[0]) ? edges[i] : (uint32_t)rt_rng_next(&rng);
        double c, s;
        rt_sample_cos_sin_turn(q, &c, &s);
        double angle = 6.283185307179586 * ((double)q / 4294967296.0);
        double err = fmax(fabs(c - cos(angle)), fabs(s - sin(angle)));
        if (err > worst) {
            worst = err;
            worst_q = q;
        }
    }
    printf("cos/sin: worst error against libm %.3g (at q = 0x%08x)\n", worst, worst_q);
    CHECK_NEAR(worst, 0.0, 1e-10);
    double c, s;
    rt_sample_cos_sin_turn(0x40000000, &c, &s); /* a quarter turn, exactly */
    CHECK_NEAR(c, 0.0, 0.0);
    CHECK_NEAR(s, 1.0, 0.0);
}

static void check_unit_vector(void)
{
    rt_rng rng = rt_rng_for_stream(11, RT_STREAM_TEST);
    const long N = 400000;
    double m[3] = {0, 0, 0}, m2[3] = {0, 0, 0}, worst_len = 0, zmax = 0;
    for (long i = 0; i < N; i++) {
        rt_vec3 v = rt_sample_unit_vector(&rng);
        worst_len = fmax(worst_len, fabs(rt_v3_len(v) - 1.0));
        zmax = fmax(zmax, fabs(v.z));
        double p[3] = {v.x, v.y, v.z};
        for (int k = 0; k < 3; k++) {
            m[k] += p[k];
            m2[k] += p[k] * p[k];
        }
    }
    printf("unit vector: worst | |v| - 1 | %.3g, max |z| %.17g\n", worst_len, zmax);
    CHECK_NEAR(worst_len, 0.0, 1e-10); /* the polynomials' truncation error */
    CHECK(zmax < 1.0);
    /* uniform on the sphere: mean 0, E[x^2] = 1/3 per axis; standard errors
     * are about 1/sqrt(3N) and 0.3/sqrt(N), checked at 5 sigma */
    for (int k = 0; k < 3; k++) {
        printf("axis %d: mean %.5f, mean square %.5f\n", k, m[k] / N, m2[k] / N);
        CHECK_NEAR(m[k] / N, 0.0, 5.0 / sqrt(3.0 * N));
        CHECK_NEAR(m2[k] / N, 1.0 / 3.0, 5.0 * 0.3 / sqrt((double)N));
    }
}

int main(void)
{
    check_cos_sin();
    check_unit_vector();
    CHECK_DONE();
}
