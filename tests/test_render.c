/* test_render.c - the determinism contract at the core: any split of the
 * work (bands, sample ranges, thread counts) sums to identical bits. */
#include <stdlib.h>
#include <string.h>

#include "accel.h"
#include "check.h"
#include "image.h"
#include "render.h"
#include "status.h"

int main(void)
{
    rt_scene s;
    CHECK_EQ_INT(rt_scene_build_final(&s, 5, 3), RT_OK);
    rt_accel *a;
    CHECK_EQ_INT(rt_accel_new(&a, &s, RT_ACCEL_BVH), RT_OK);
    rt_render_params p = {40, 24, 6, 20, 5, RT_DIFFUSE_LAMBERTIAN};
    rt_renderer r;
    CHECK_EQ_INT(rt_render_init(&r, &s, a, &p), RT_OK);
    size_t n = (size_t)p.width * p.height * 3;
    int64_t *ref = calloc(n, sizeof *ref), *alt = calloc(n, sizeof *alt);
    uint64_t segs_ref = rt_render_rows(&r, 0, p.height, 0, p.samples, ref, 1, NULL, NULL);
    CHECK(segs_ref >= (uint64_t)p.width * p.height * p.samples);

    /* Bands of 5 rows, two threads. */
    uint64_t segs = 0;
    for (uint32_t y = 0; y < p.height; y += 5) {
        uint32_t y1 = y + 5 < p.height ? y + 5 : p.height;
        segs += rt_render_rows(&r, y, y1, 0, p.samples, alt + (size_t)y * p.width * 3, 2, NULL, NULL);
    }
    CHECK(memcmp(ref, alt, n * sizeof *ref) == 0);
    CHECK_EQ_U64(segs, segs_ref);

    /* Sample ranges 0-1, 1-4, 4-6 added in a scrambled order. */
    memset(alt, 0, n * sizeof *alt);
    rt_render_rows(&r, 0, p.height, 4, 6, alt, 2, NULL, NULL);
    rt_render_rows(&r, 0, p.height, 0, 1, alt, 1, NULL, NULL);
    rt_render_rows(&r, 0, p.height, 1, 4, alt, 3, NULL, NULL);
    CHECK(memcmp(ref, alt, n * sizeof *ref) == 0);

    /* Brute force gives the same image as the BVH. */
    rt_accel *brute;
    CHECK_EQ_INT(rt_accel_new(&brute, &s, RT_ACCEL_BRUTE), RT_OK);
    rt_renderer rb;
    CHECK_EQ_INT(rt_render_init(&rb, &s, brute, &p), RT_OK);
    memset(alt, 0, n * sizeof *alt);
    rt_render_rows(&rb, 0, p.height, 0, p.samples, alt, 2, NULL, NULL);
    CHECK(memcmp(ref, alt, n * sizeof *ref) == 0);

    /* A different seed gives a different image. */
    rt_render_params q = p;
    q.seed = 6;
    rt_renderer r2;
    CHECK_EQ_INT(rt_render_init(&r2, &s, a, &q), RT_OK);
    memset(alt, 0, n * sizeof *alt);
    rt_render_rows(&r2, 0, p.height, 0, p.samples, alt, 1, NULL, NULL);
    CHECK(memcmp(ref, alt, n * sizeof *ref) != 0);

    /* The rays a sample traces (bench_accel's input): as many as the
     * segments it counts, each from where the previous one hit. */
    rt_ray *path = malloc(p.max_depth * sizeof *path);
    CHECK(path != NULL);
    long total_rays = 0, total_segs = 0, chained = 1;
    for (uint32_t k = 0; k < 200; k++) {
        uint64_t segs = 0;
        rt_render_sample(&r, k % p.width, k % p.height, k, &segs);
        uint32_t m = rt_render_sample_rays(&r, k % p.width, k % p.height, k, path);
        total_rays += m;
        total_segs += (long)segs;
        for (uint32_t i = 1; i < m; i++) {
            rt_hit h;
            chained &= rt_accel_closest(a, &path[i - 1], 0.001, INFINITY, &h) &&
                       rt_v3_len(rt_v3_sub(rt_ray_at(&path[i - 1], h.t), path[i].orig)) == 0.0;
        }
    }
    CHECK_EQ_INT(total_rays, total_segs);
    CHECK(total_rays > 200);
    CHECK(chained);
    free(path);

    /* Tone mapping: the book's gamma 2 and 0.999 clamp. */
    int64_t px[6] = {0, (int64_t)(0.25 * RT_FIX_ONE) * 4, (int64_t)(4.0 * RT_FIX_ONE) * 4, 0, 0, 0};
    uint8_t out[6];
    rt_image_to_rgb8(px, 2, 4, out);
    CHECK_EQ_INT(out[0], 0);
    CHECK_EQ_INT(out[1], 128); /* sqrt(0.25) * 256 */
    CHECK_EQ_INT(out[2], 255); /* clamped to 0.999 */
    CHECK_EQ_INT(rt_render_fix(-1.0), 0);
    CHECK_EQ_INT(rt_render_fix(NAN), 0);
    CHECK_EQ_INT(rt_render_fix(1e9), (int64_t)(RT_SAMPLE_MAX * RT_FIX_ONE));
    free(ref);
    free(alt);
    rt_accel_free(a);
    rt_accel_free(brute);
    rt_scene_free(&s);
    CHECK_DONE();
}
