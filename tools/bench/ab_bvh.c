/* ab_bvh.c - A/B timing of two versions of the BVH on the same rays: the
 * working tree's src/bvh.c (A) against another bvh.c (B) compiled in with
 * its rt_bvh_* symbols renamed ab_bvh_* (scripts/ab_bvh.sh builds it). The
 * rays are every segment of the renderer's paths in the final scene; the
 * two versions alternate round by round so a drift in the machine's speed
 * hits both; the best round of each is reported. Any ray on which the two
 * disagree (hit against miss, or another t) fails the run.
 * Usage: ab_bvh [WIDTH [SAMPLES [ROUNDS]]] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "accel.h"
#include "bench_rays.h"
#include "bvh.h"
#include "clock.h"
#include "render.h"
#include "scene.h"

int ab_bvh_build(rt_bvh **out, const rt_scene *s);
int ab_bvh_closest(const rt_bvh *b, const rt_ray *ray, double tmin, double tmax, rt_hit *hit);
void ab_bvh_free(rt_bvh *b);

typedef int (*closest_fn)(const rt_bvh *, const rt_ray *, double, double, rt_hit *);

static volatile double sink;

static double round_ns(closest_fn f, const rt_bvh *b, const rt_ray *rays, size_t n)
{
    double sum = 0, t0 = rt_now();
    for (size_t i = 0; i < n; i++) {
        rt_hit h;
        if (f(b, &rays[i], 0.001, INFINITY, &h))
            sum += h.t;
    }
    double ns = (rt_now() - t0) * 1e9 / (double)n;
    sink = sum;
    return ns;
}

int main(int argc, char **argv)
{
    uint32_t W = argc > 1 ? (uint32_t)atoi(argv[1]) : 300, S = argc > 2 ? (uint32_t)atoi(argv[2]) : 8;
    int rounds = argc > 3 ? atoi(argv[3]) : 7;
    if (W < 2 || S < 1 || rounds < 1) {
        fprintf(stderr, "usage: ab_bvh [WIDTH [SAMPLES [ROUNDS]]]\n");
        return 2;
    }
    rt_scene s;
    rt_accel *accel = NULL;
    rt_bvh *a = NULL, *b = NULL;
    rt_renderer r;
    rt_job p = {W, W * 2 / 3, S, 50, 42, RT_DIFFUSE_LAMBERTIAN, RT_SAMPLER_RANDOM, 0, 0};
    if (rt_scene_build_final(&s, 42, 11) || rt_accel_new(&accel, &s, RT_ACCEL_BVH) || rt_bvh_build(&a, &s) ||
        ab_bvh_build(&b, &s) || rt_render_init(&r, &s, accel, &p)) {
        fprintf(stderr, "ab_bvh: cannot set up the scene\n");
        return 1;
    }
    rt_ray *rays;
    size_t n;
    if (bench_capture_rays(&r, &rays, &n, NULL)) {
        fprintf(stderr, "ab_bvh: out of memory\n");
        return 1;
    }
    size_t bad = 0;
    for (size_t i = 0; i < n; i++) {
        rt_hit ha = {0, 0}, hb = {0, 0};
        int xa = rt_bvh_closest(a, &rays[i], 0.001, INFINITY, &ha);
        int xb = ab_bvh_closest(b, &rays[i], 0.001, INFINITY, &hb);
        bad += bench_hits_differ(xa, &ha, xb, &hb);
    }
    double best_a = INFINITY, best_b = INFINITY;
    for (int q = 0; q < rounds; q++) {
        double ta = round_ns(rt_bvh_closest, a, rays, n), tb = round_ns(ab_bvh_closest, b, rays, n);
        best_a = ta < best_a ? ta : best_a;
        best_b = tb < best_b ? tb : best_b;
    }
    printf("ab_bvh: %zu rays of the final scene (%ux%u, %u spp), best of %d alternating rounds, 1 thread\n", n, W,
           p.height, S, rounds);
    printf("  A (working tree)  %7.2f ns/ray\n  B                 %7.2f ns/ray\n  A / B speed       %7.3f\n", best_a,
           best_b, best_b / best_a);
    if (bad)
        fprintf(stderr, "ab_bvh: A and B disagree on %zu of %zu rays\n", bad, n);
    free(rays);
    rt_bvh_free(a);
    ab_bvh_free(b);
    rt_accel_free(accel);
    rt_scene_free(&s);
    return bad != 0;
}
