/* test_aov.c - the denoiser's buffers (--aov albedo,normal): the albedo
 * and shading normal of each sample's first non-specular hit, summed like
 * its colour:
 * - through glass and a perfect mirror, inside a lambertian room of albedo
 *   b (no light gets in: the colour is black), every sample ends on the
 *   room: each pixel's albedo is exactly b;
 * - a fuzzy metal sphere's pixel takes its albedo, and a normal that faces
 *   the camera; a sky pixel the sky's colour and a zero normal;
 * - the colour is the same bits with or without the buffers, and with
 *   adaptive sampling the buffers follow each pixel's own count. */
#include <stdlib.h>
#include <string.h>

#include "accel.h"
#include "check.h"
#include "core_internal.h"
#include "render.h"
#include "status.h"

typedef struct image {
    rt_renderer r;
    int64_t *acc;
} image;

static void render(image *im, const rt_scene *s, const rt_accel *a, uint32_t aov, double threshold, int roulette)
{
    rt_job p = {30, 20, 64, 50, 9, RT_DIFFUSE_LAMBERTIAN, RT_SAMPLER_SOBOL, roulette, 0, threshold, aov, RT_LIGHT_MIS};
    CHECK_EQ_INT(rt_render_init(&im->r, s, a, &p), RT_OK);
    im->acc = calloc((size_t)p.width * p.height * im->r.lay.ch, sizeof *im->acc);
    rt_render_rows(&im->r, 0, p.height, 0, p.samples, im->acc, 2);
}

static const int64_t *pixel(const image *im, uint32_t x, uint32_t y)
{
    return im->acc + ((size_t)y * im->r.job.width + x) * im->r.lay.ch;
}

/* The unit vector of a pixel's normal sums. */
static rt_vec3 normal_of(const image *im, uint32_t x, uint32_t y)
{
    const int64_t *n = pixel(im, x, y) + im->r.lay.normal;
    return rt_v3_unit(rt_v3((double)n[0], (double)n[1], (double)n[2]));
}

static void check_room(void)
{
    const rt_vec3 b = rt_v3(0.3, 0.5, 0.7);
    rt_scene s;
    rt_scene_init(&s);
    CHECK_EQ_INT(rt_scene_add(&s, rt_v3(0, 0, 0), 100.0, rt_scene_lambertian(b)), RT_OK);
    CHECK_EQ_INT(rt_scene_add(&s, rt_v3(0, 0, -3), 1.0, rt_scene_dielectric(1.5)), RT_OK);
    CHECK_EQ_INT(rt_scene_add(&s, rt_v3(1.3, 0.2, -2.5), 0.5, rt_scene_metal(rt_v3(0.9, 0.9, 0.9), 0.0)), RT_OK);
    s.camera = (rt_camera_desc){rt_v3(0, 0, 0), rt_v3(0, 0, -1), rt_v3(0, 1, 0), 60.0, 0.0, 3.0, 0};
    rt_accel *a;
    CHECK_EQ_INT(rt_accel_new(&a, &s, RT_ACCEL_BVH), RT_OK);
    image im;
    /* no roulette: it could end a path on the glass or the mirror, which
     * then gives that surface's albedo (path.h) */
    render(&im, &s, a, RT_AOV_ALBEDO | RT_AOV_NORMAL, 0, 0);

    CHECK_EQ_INT(im.r.lay.ch, 9);
    const int64_t want[3] = {64 * rt_render_fix(b.x), 64 * rt_render_fix(b.y), 64 * rt_render_fix(b.z)};
    unsigned not_b = 0;
    for (uint32_t y = 0; y < 20; y++)
        for (uint32_t x = 0; x < 30; x++) {
            const int64_t *px = pixel(&im, x, y);
            not_b += memcmp(px + im.r.lay.albedo, want, sizeof want) != 0;
        }
    /* through glass and mirror on to the room: all but a sample that
     * grazes the mirror's rim (absorbed there: it keeps the mirror's
     * albedo); the pixels through the glass's and the mirror's centres */
    printf("room: %u of 600 pixels not exactly the room's albedo\n", not_b);
    CHECK(not_b <= 2);
    CHECK(!memcmp(pixel(&im, 15, 10) + im.r.lay.albedo, want, sizeof want));
    CHECK(!memcmp(pixel(&im, 24, 8) + im.r.lay.albedo, want, sizeof want));
    /* the mirror's centre shows the wall behind the camera: a normal
     * along the view ray, where the wall seen directly faces it */
    CHECK(rt_v3_dot(normal_of(&im, 24, 8), rt_v3(0, 0, -1)) > 0.5);
    /* the corner pixel sees the room's wall: its normal faces the camera */
    rt_vec3 n = normal_of(&im, 0, 0), dir = rt_v3_unit(rt_v3(-1.5 * tan(0.5236), tan(0.5236), -1));
    printf("room: corner normal %.4f %.4f %.4f, against the view ray %.5f\n", n.x, n.y, n.z, rt_v3_dot(n, dir));
    CHECK(rt_v3_dot(n, dir) < -0.99);
    free(im.acc);
    rt_accel_free(a);
    rt_scene_free(&s);
}

static void check_metal_and_sky(void)
{
    const rt_vec3 m = rt_v3(0.8, 0.4, 0.2), sky = rt_v3(0.9, 0.8, 0.7);
    /* a sky of one colour in x and y, a gradient in z (the adaptive
     * sampling goes on past pixels whose samples are all equal) */
    rt_scene s;
    rt_scene_init(&s);
    CHECK_EQ_INT(rt_scene_add(&s, rt_v3(0, 0, -3), 1.0, rt_scene_metal(m, 0.5)), RT_OK);
    s.sky_bottom = sky;
    s.sky_top = rt_v3(sky.x, sky.y, 1.0);
    s.camera = (rt_camera_desc){rt_v3(0, 0, 0), rt_v3(0, 0, -1), rt_v3(0, 1, 0), 60.0, 0.0, 3.0, 0};
    rt_accel *a;
    CHECK_EQ_INT(rt_accel_new(&a, &s, RT_ACCEL_BVH), RT_OK);
    for (int adaptive = 0; adaptive < 2; adaptive++) {
        image im;
        render(&im, &s, a, RT_AOV_ALBEDO | RT_AOV_NORMAL, adaptive ? 0.05 : 0, 1);
        const rt_layout *l = &im.r.lay;
        CHECK_EQ_INT(l->ch, adaptive ? 10 : 9);
        const int64_t *c = pixel(&im, 15, 10), *k = pixel(&im, 0, 0);
        const int64_t nc = adaptive ? c[l->count] : 64, nk = adaptive ? k[l->count] : 64;
        printf("metal and sky%s: %lld and %lld samples\n", adaptive ? ", adaptive" : "", (long long)nc,
               (long long)nk);
        CHECK_EQ_INT(c[l->albedo], nc * rt_render_fix(m.x));
        CHECK_EQ_INT(c[l->albedo + 1], nc * rt_render_fix(m.y));
        CHECK_EQ_INT(c[l->albedo + 2], nc * rt_render_fix(m.z));
        CHECK(normal_of(&im, 15, 10).z > 0.99);
        CHECK_NEAR((double)k[l->albedo] / RT_FIX_ONE / (double)nk, sky.x, 1e-9);
        CHECK_NEAR((double)k[l->albedo + 1] / RT_FIX_ONE / (double)nk, sky.y, 1e-9);
        CHECK_EQ_INT(k[l->normal] | k[l->normal + 1] | k[l->normal + 2], 0);
        if (adaptive) /* the sky is smooth: it stops at the first count */
            CHECK_EQ_INT(nk, RT_ADAPT_FIRST);
        /* the buffers change no bit of the colour or the counts */
        image plain;
        render(&plain, &s, a, 0, adaptive ? 0.05 : 0, 1);
        unsigned differ = 0;
        for (uint32_t y = 0; y < 20; y++)
            for (uint32_t x = 0; x < 30; x++) {
                differ += memcmp(pixel(&im, x, y), pixel(&plain, x, y), 3 * sizeof(int64_t)) != 0;
                if (adaptive)
                    differ += pixel(&im, x, y)[l->count] != pixel(&plain, x, y)[plain.r.lay.count];
            }
        CHECK_EQ_INT(differ, 0);
        free(plain.acc);
        free(im.acc);
    }
    rt_accel_free(a);
    rt_scene_free(&s);
}

int main(void)
{
    check_room();
    check_metal_and_sky();
    CHECK_DONE();
}
