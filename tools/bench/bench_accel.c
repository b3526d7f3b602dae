/* bench_accel.c - the intersectors alone, side by side: the rays the
 * renderer traces for the final scene (every segment of every path) are
 * captured once, then each intersector finds their closest hits on one
 * thread. This isolates the acceleration structure from the shading,
 * sampling and RNG that every intersector shares in a full render.
 * scripts/bench.sh runs it; usage: bench_accel [WIDTH [SAMPLES [BRUTE_EVERY]]] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core_internal.h"
#include "accel.h"
#include "bench_rays.h"
#include "bvh.h"
#include "primary.h"
#include "clock.h"
#include "render.h"
#include "scene.h"
#include "status.h"

static volatile double sink;

/* Nanoseconds per closest-hit query over rays[0], rays[every], ...; the
 * best of three rounds. The hits feed a sum so no query can be dropped. */
static double time_kind(const rt_accel *a, const rt_ray *rays, size_t n, size_t every)
{
    double best = 1e30;
    for (int k = 0; k < 3; k++) {
        double sum = 0;
        size_t count = 0;
        double t0 = rt_now();
        for (size_t i = 0; i < n; i += every, count++) {
            rt_hit h;
            if (rt_accel_closest(a, &rays[i], 0.001, INFINITY, &h))
                sum += h.t;
        }
        double ns = (rt_now() - t0) * 1e9 / (double)count;
        best = ns < best ? ns : best;
        sink = sum;
    }
    return best;
}

/* Our BVH timed class by class, each class's rays on their own: rays that
 * hit nothing (the sky), that end on the largest sphere (the final scene's
 * ground), and that end on another sphere. Shows whether some kind of ray
 * is an outlier worth a special path. */
static void time_classes(const rt_accel *bvh, const rt_scene *s, const rt_ray *rays, size_t n)
{
    static const char *names[3] = {"hit nothing (sky)", "end on the largest sphere", "end on another sphere"};
    uint32_t largest = 0;
    for (uint32_t i = 1; i < s->n_spheres; i++)
        if (fabs(s->spheres[i].radius) > fabs(s->spheres[largest].radius))
            largest = i;
    rt_ray *cls[3];
    size_t count[3] = {0, 0, 0};
    for (int c = 0; c < 3; c++)
        cls[c] = malloc((n ? n : 1) * sizeof *rays);
    if (!cls[0] || !cls[1] || !cls[2]) {
        fprintf(stderr, "bench_accel: out of memory for the ray classes\n");
        exit(1);
    }
    /* Classified by the counted traversal (untimed), which also gives each
     * class its nodes visited and spheres tested. */
    rt_bvh_counts k[3] = {{0, 0}, {0, 0}, {0, 0}};
    for (size_t i = 0; i < n; i++) {
        rt_hit h;
        rt_bvh_counts one = {0, 0};
        int c = 0;
        if (rt_bvh_closest_counted(rt_accel_bvh(bvh), &rays[i], 0.001, INFINITY, &h, &one))
            c = h.prim == largest ? 1 : 2;
        cls[c][count[c]++] = rays[i];
        k[c].nodes += one.nodes;
        k[c].spheres += one.spheres;
    }
    double per = 1.0 / (double)(n ? n : 1);
    printf("bvh by ray class (each class timed on its own; nodes visited and spheres tested per ray):\n");
    printf("  %-26s %5.1f %% of rays  %6s        %5.2f nodes  %5.2f spheres\n", "all rays", 100.0, "",
           (double)(k[0].nodes + k[1].nodes + k[2].nodes) * per,
           (double)(k[0].spheres + k[1].spheres + k[2].spheres) * per);
    for (int c = 0; c < 3; c++) {
        if (count[c])
            printf("  %-26s %5.1f %% of rays  %6.1f ns/ray  %5.2f nodes  %5.2f spheres\n", names[c],
                   100.0 * (double)count[c] * per, time_kind(bvh, cls[c], count[c], 1),
                   (double)k[c].nodes / (double)count[c], (double)k[c].spheres / (double)count[c]);
        free(cls[c]);
    }
}

/* Rays among rays[0], rays[every], ... on which two exact intersectors
 * disagree (bench_hits_differ). Untimed. */
static size_t disagreements(const rt_accel *x, const rt_accel *y, const rt_ray *rays, size_t n, size_t every)
{
    size_t bad = 0;
    for (size_t i = 0; i < n; i += every) {
        rt_hit hx = {0, 0}, hy = {0, 0};
        int a = rt_accel_closest(x, &rays[i], 0.001, INFINITY, &hx);
        int b = rt_accel_closest(y, &rays[i], 0.001, INFINITY, &hy);
        bad += bench_hits_differ(a, &hx, b, &hy);
    }
    return bad;
}

/* Our BVH on the rays captured (rays[0, n), the paths' lengths in lens)
 * grouped as the renderer's AVX path loop groups them (render.c, pixel): the
 * camera rays of a pixel whose tile has a list (pl, primary.h) go through
 * that list; a pixel's samples eight at a time, whose camera rays (when
 * there is no list) and later segments while all eight paths live go to
 * rt_bvh_closest_packet as one packet; then each path still live goes on to
 * its end one ray at a time. Prints the time per ray of each part, and of
 * all (against tb, the same rays one at a time in render order, and tf,
 * brute force); returns the rays whose packet or list answer differs from
 * their own query's (untimed). */
static size_t time_packets(const rt_bvh *b, const rt_primary *pl, const rt_job *p, const rt_ray *rays,
                           size_t n, const uint32_t *lens, double tb, double tf)
{
    const uint32_t S = p->samples;
    size_t np = 0, ns = 0, nl = 0, npk = 0, at = 0, path = 0;
    rt_ray *pk = malloc(n * sizeof *pk), *sg = malloc(n * sizeof *sg), *ls = malloc(n * sizeof *ls);
    int *sizes = malloc(n * sizeof *sizes);
    uint32_t *lfirst = malloc(n * sizeof *lfirst);
    int32_t *ln = malloc(n * sizeof *ln);
    if (!pk || !sg || !ls || !sizes || !lfirst || !ln) {
        fprintf(stderr, "bench_accel: out of memory for the packets\n");
        exit(1);
    }
    for (size_t pixel = 0; pixel < (size_t)p->width * p->height; pixel++) {
        uint32_t first_cand = 0;
        const int32_t list = rt_primary_tile(pl, (uint32_t)(pixel % p->width), (uint32_t)(pixel / p->width), &first_cand);
        for (uint32_t s0 = 0; s0 < S; s0 += RT_RENDER_PACKET) {
            const uint32_t g = S - s0 < RT_RENDER_PACKET ? S - s0 : RT_RENDER_PACKET;
            const rt_ray *first[RT_RENDER_PACKET];
            uint32_t all_live = p->max_depth;
            for (uint32_t k = 0; k < g; k++, path++) {
                first[k] = rays + at;
                at += lens[path];
                all_live = lens[path] < all_live ? lens[path] : all_live;
            }
            /* the camera rays through the pixel's list when it has one,
             * then the segments up to pend in packets */
            uint32_t d0 = 0;
            if (list >= 0) {
                for (uint32_t k = 0; k < g; k++) {
                    lfirst[nl] = first_cand;
                    ln[nl] = list;
                    ls[nl++] = first[k][0];
                }
                d0 = 1;
            }
            uint32_t pend = d0;
            while (pend < p->max_depth && rt_render_in_packet((int)g, pend < all_live, pend))
                pend++;
            for (uint32_t d = d0; d < pend; d++) {
                for (uint32_t k = 0; k < g; k++)
                    pk[np++] = first[k][d];
                sizes[npk++] = (int)g;
            }
            /* then each live path to its end, one ray at a time */
            for (uint32_t k = 0; k < g; k++)
                for (uint32_t d = pend; d < lens[path - g + k]; d++)
                    sg[ns++] = first[k][d];
        }
    }
    double best_p = 1e30, best_s = 1e30, best_l = 1e30;
    for (int round = 0; round < 3; round++) {
        double sum = 0, tl = rt_now();
        rt_hit h[8];
        for (size_t i = 0; i < nl; i++)
            if (rt_primary_closest(pl, lfirst[i], ln[i], &ls[i], 0.001, INFINITY, h))
                sum += h[0].t;
        double t0 = rt_now();
        for (size_t i = 0, at = 0; i < npk; at += (size_t)sizes[i++]) {
            int f = rt_bvh_closest_packet(b, pk + at, sizes[i], 0.001, INFINITY, h);
            sum += f ? h[__builtin_ctz((unsigned)f)].t : 0;
        }
        double t1 = rt_now();
        for (size_t i = 0; i < ns; i++)
            if (rt_bvh_closest(b, &sg[i], 0.001, INFINITY, h))
                sum += h[0].t;
        double t2 = rt_now();
        best_l = fmin(best_l, (t0 - tl) * 1e9 / (double)(nl ? nl : 1));
        best_p = fmin(best_p, (t1 - t0) * 1e9 / (double)(np ? np : 1));
        best_s = fmin(best_s, (t2 - t1) * 1e9 / (double)ns);
        sink = sum;
    }
    size_t bad = 0;
    for (size_t i = 0, at = 0; i < npk; at += (size_t)sizes[i++]) {
        rt_hit h[8];
        int f = rt_bvh_closest_packet(b, pk + at, sizes[i], 0.001, INFINITY, h);
        for (int k = 0; k < sizes[i]; k++) {
            rt_hit one = {0, 0};
            int x1 = rt_bvh_closest(b, pk + at + k, 0.001, INFINITY, &one);
            bad += bench_hits_differ((f >> k) & 1, &h[k], x1, &one);
        }
    }
    for (size_t i = 0; i < nl; i++) {
        rt_hit one = {0, 0}, h = {0, 0};
        int x0 = rt_primary_closest(pl, lfirst[i], ln[i], &ls[i], 0.001, INFINITY, &h);
        int x1 = rt_bvh_closest(b, &ls[i], 0.001, INFINITY, &one);
        bad += bench_hits_differ(x0, &h, x1, &one);
    }
    const double total = (double)(np + ns + nl);
    double all = (best_p * (double)np + best_s * (double)ns + best_l * (double)nl) / total;
    printf("bvh on the rays grouped as the renderer groups them (%s, camera-ray lists):\n",
           rt_bvh_uses_avx(b) ? "avx packets of up to 8 rays" : "no AVX: one at a time");
    printf("  camera rays through their tile's list  %5.1f %% of rays  %6.1f ns/ray\n", 100.0 * (double)nl / total,
           best_l);
    printf("  in packets                             %5.1f %% of rays  %6.1f ns/ray\n", 100.0 * (double)np / total,
           best_p);
    printf("  one by one                             %5.1f %% of rays  %6.1f ns/ray\n", 100.0 * (double)ns / total,
           best_s);
    printf("  all rays                                                %6.1f ns/ray  (%.2fx the rays one at a time in "
           "render order)\n",
           all,
           tb / all);
    printf("  bvh / brute speed:   %.2f\n", tf / all);
    free(pk);
    free(sg);
    free(ls);
    free(sizes);
    free(lfirst);
    free(ln);
    return bad;
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
    rt_accel *bvh = NULL, *sse = NULL, *brute = NULL, *embree = NULL;
    if (rt_scene_build_final(&s, 42, 11) || rt_accel_new(&bvh, &s, RT_ACCEL_BVH) ||
        rt_accel_new(&sse, &s, RT_ACCEL_BVH_SSE) || rt_accel_new(&brute, &s, RT_ACCEL_BRUTE)) {
        fprintf(stderr, "bench_accel: cannot build the scene\n");
        return 1;
    }
    int have_embree = rt_accel_new(&embree, &s, RT_ACCEL_EMBREE) == RT_OK;
    rt_job p = {W, H, S, 50, 42, RT_DIFFUSE_LAMBERTIAN, RT_SAMPLER_RANDOM, 0, 0, 0, 0, RT_LIGHT_MIS};
    rt_renderer r;
    rt_ray *rays;
    uint32_t *lens;
    size_t n;
    if (rt_render_init(&r, &s, bvh, &p)) {
        fprintf(stderr, "bench_accel: cannot set up the renderer\n");
        return 1;
    }
    if (bench_capture_rays(&r, &rays, &n, &lens)) {
        fprintf(stderr, "bench_accel: out of memory\n");
        return 1;
    }
    printf("bench_accel: final scene, %ux%u, %u spp: %zu rays from the renderer's paths, %u spheres\n", W, H, S, n,
           s.n_spheres);
    printf("closest hit only, 1 thread, best of 3 (brute force on every %zu-th ray):\n", every);
    double tb = time_kind(bvh, rays, n, 1), ts = time_kind(sse, rays, n, 1), tf = time_kind(brute, rays, n, every);
    printf("  bvh     %8.1f ns/ray  (%s box test)\n", tb, rt_accel_box_test(bvh));
    printf("  bvh-sse %8.1f ns/ray  (%s box test)\n", ts, rt_accel_box_test(sse));
    printf("  brute   %8.1f ns/ray\n", tf);
    if (have_embree) {
        double te = time_kind(embree, rays, n, 1);
        printf("  embree  %8.1f ns/ray\n", te);
        printf("  bvh / embree speed:  %.2f\n", te / tb);
    }
    printf("  bvh / brute speed:   %.2f\n", tf / tb);
    time_classes(bvh, &s, rays, n);
    rt_primary *pl;
    if (rt_primary_build(&pl, &s, &r.camera, W, H)) {
        fprintf(stderr, "bench_accel: cannot build the camera-ray lists\n");
        return 1;
    }
    size_t bad_packets = time_packets(rt_accel_bvh(bvh), pl, &p, rays, n, lens, tb, tf);
    rt_primary_free(pl);
    if (bad_packets)
        fprintf(stderr, "bench_accel: packets or lists and single queries disagree on %zu rays\n", bad_packets);
    size_t bad = disagreements(bvh, brute, rays, n, every), checked = (n + every - 1) / every;
    if (bad)
        fprintf(stderr, "bench_accel: bvh and brute force disagree on %zu of the %zu rays compared\n", bad, checked);
    size_t bad_sse = disagreements(bvh, sse, rays, n, 1);
    if (bad_sse)
        fprintf(stderr, "bench_accel: bvh and bvh-sse disagree on %zu of the %zu rays\n", bad_sse, n);
    bad += bad_sse + bad_packets;
    rt_accel_free(embree);
    rt_accel_free(brute);
    rt_accel_free(sse);
    rt_accel_free(bvh);
    rt_scene_free(&s);
    free(rays);
    free(lens);
    return bad != 0;
}
