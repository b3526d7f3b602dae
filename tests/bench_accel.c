/* bench_accel.c - the intersectors alone, side by side: the rays the
 * renderer traces for the final scene (every segment of every path) are
 * captured once, then each intersector finds their closest hits on one
 * thread. This isolates the acceleration structure from the shading,
 * sampling and RNG that every intersector shares in a full render.
 * scripts/bench.sh runs it; usage: bench_accel [WIDTH [SAMPLES [BRUTE_EVERY]]] */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "accel.h"
#include "render.h"
#include "scene.h"
#include "status.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

typedef struct result {
    double ns; /* best time per ray */
    uint64_t check;
} result;

/* Closest hits of rays[0], rays[every], ...; best of `rounds`. */
static result time_kind(const rt_accel *a, const rt_ray *rays, size_t n, size_t every, int rounds)
{
    result res = {1e30, 0};
    for (int k = 0; k < rounds; k++) {
        uint64_t check = 0;
        size_t count = 0;
        double t0 = now();
        for (size_t i = 0; i < n; i += every, count++) {
            rt_hit h;
            if (rt_accel_closest(a, &rays[i], 0.001, INFINITY, &h))
                check = check * 31 + h.prim + 1;
            else
                check = check * 31;
        }
        double ns = (now() - t0) * 1e9 / (double)count;
        res.ns = ns < res.ns ? ns : res.ns;
        res.check = check;
    }
    return res;
}

int main(int argc, char **argv)
{
    uint32_t W = argc > 1 ? (uint32_t)atoi(argv[1]) : 300, S = argc > 2 ? (uint32_t)atoi(argv[2]) : 8;
    size_t every = argc > 3 ? (size_t)atoi(argv[3]) : 16;
    if (W < 2 || S < 1 || every < 1) {
        fprintf(stderr, "usage: bench_accel [WIDTH [SAMPLES [BRUTE_EVERY]]]\n");
        return 2;
    }
    uint32_t H = W * 2 / 3;
    rt_scene s;
    rt_accel *bvh = NULL, *brute = NULL, *embree = NULL;
    if (rt_scene_build_final(&s, 42, 11) || rt_accel_new(&bvh, &s, RT_ACCEL_BVH) ||
        rt_accel_new(&brute, &s, RT_ACCEL_BRUTE)) {
        fprintf(stderr, "bench_accel: cannot build the scene\n");
        return 1;
    }
    int have_embree = rt_accel_new(&embree, &s, RT_ACCEL_EMBREE) == RT_OK;
    rt_render_params p = {W, H, S, 50, 42, RT_DIFFUSE_LAMBERTIAN};
    rt_renderer r;
    size_t cap = (size_t)W * H * S * 3 + p.max_depth, n = 0;
    rt_ray *rays = malloc(cap * sizeof *rays);
    if (!rays || rt_render_init(&r, &s, bvh, &p)) {
        fprintf(stderr, "bench_accel: out of memory\n");
        return 1;
    }
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            for (uint32_t k = 0; k < S; k++) {
                if (n + p.max_depth > cap) {
                    cap *= 2;
                    rt_ray *q = realloc(rays, cap * sizeof *rays);
                    if (!q) {
                        fprintf(stderr, "bench_accel: out of memory\n");
                        return 1;
                    }
                    rays = q;
                }
                n += rt_render_sample_rays(&r, x, y, k, rays + n);
            }
    printf("bench_accel: final scene, %ux%u, %u spp: %zu rays from the renderer's paths, %u spheres\n", W, H, S, n,
           s.n_spheres);
    printf("closest hit only, 1 thread, best of 3 (brute force on every %zu-th ray):\n", every);
    result rb = time_kind(bvh, rays, n, 1, 3), rbe = time_kind(bvh, rays, n, every, 3);
    result rf = time_kind(brute, rays, n, every, 3);
    printf("  bvh     %8.1f ns/ray\n", rb.ns);
    printf("  brute   %8.1f ns/ray\n", rf.ns);
    int bad = rbe.check != rf.check;
    if (have_embree) {
        result re = time_kind(embree, rays, n, 1, 3);
        printf("  embree  %8.1f ns/ray\n", re.ns);
        printf("  bvh / embree speed:  %.2f\n", re.ns / rb.ns);
    }
    printf("  bvh / brute speed:   %.2f\n", rf.ns / rb.ns);
    if (bad)
        fprintf(stderr, "bench_accel: bvh and brute force disagree on the same rays\n");
    rt_accel_free(embree);
    rt_accel_free(brute);
    rt_accel_free(bvh);
    rt_scene_free(&s);
    free(rays);
    return bad;
}
