/* scenes_book2.c - the scenes of "Ray Tracing: The Next Week" (v4), with
 * the book's cameras and backgrounds; their random spheres and boxes come
 * from the seed's scene stream, as book 1's final scene's do. */
#include "scenes_book2.h"

#include <string.h>

#include "rng.h"
#include "status.h"
#include "xform.h"

/* The books' v4 camera: defocus_angle degrees -> our aperture (the lens
 * disk's diameter at the focus distance). */
static void camera(rt_scene *s, rt_vec3 from, rt_vec3 at, double vfov, double defocus_deg, double focus)
{
    rt_camera_desc *c = &s->camera;
    c->lookfrom = from;
    c->lookat = at;
    c->vup = rt_v3(0, 1, 0);
    c->vfov_deg = vfov;
    c->focus_dist = focus > 0 ? focus : rt_v3_len(rt_v3_sub(from, at));
    c->aperture = defocus_deg > 0 ? 2.0 * c->focus_dist * tan(defocus_deg * (3.14159265358979323846 / 360.0)) : 0.0;
    c->pixels = RT_PIXELS_BOOK2;
}

static void background(rt_scene *s, rt_vec3 c)
{
    s->background_kind = RT_BACKGROUND_COLOR;
    s->background = c;
}

static const rt_vec3 DAYLIGHT = {0.70, 0.80, 1.00};

/* A material, returning its index through *m. */
static int mat(rt_scene *s, rt_material m, uint32_t *idx) { return rt_scene_add_material(s, &m, idx); }

/* A texture of its own: solid colour c. */
static int solid(rt_scene *s, rt_vec3 c, uint32_t *idx)
{
    rt_texture t = {.kind = RT_TEX_SOLID, .color = c};
    return rt_scene_add_texture(s, &t, idx);
}

/* The book's checker of cell size `cell` between two colours. */
static int checker(rt_scene *s, double cell, rt_vec3 even, rt_vec3 odd, uint32_t *idx)
{
    uint32_t e = 0, o = 0; /* read (and dropped) on an error too */
    int st = solid(s, even, &e);
    if (!st)
        st = solid(s, odd, &o);
    rt_texture t = {.kind = RT_TEX_CHECKER, .scale = cell, .even = e, .odd = o};
    return st ? st : rt_scene_add_texture(s, &t, idx);
}

/* Book 2's noise_texture (marble) at frequency f. */
static int marble(rt_scene *s, double f, uint32_t *idx)
{
    rt_texture t = {.kind = RT_TEX_NOISE, .color = rt_v3(1, 1, 1), .scale = f, .mode = RT_NOISE_MARBLE};
    return rt_scene_add_texture(s, &t, idx);
}

/* A lambertian material with texture tex. */
static int textured(rt_scene *s, uint32_t tex, uint32_t *idx)
{
    return mat(s, rt_scene_textured(rt_scene_lambertian(rt_v3(0, 0, 0)), tex), idx);
}

/* The earth's texture, from the image the caller read. */
static int earth_texture(rt_scene *s, const rt_scene_image *earth, uint32_t *idx)
{
    if (!earth || !earth->texels)
        return RT_ENOFILE;
    uint32_t im;
    int st = rt_scene_add_image(s, earth->width, earth->height, earth->texels, &im);
    rt_texture t = {.kind = RT_TEX_IMAGE, .image = im};
    return st ? st : rt_scene_add_texture(s, &t, idx);
}

static int bouncing_spheres(rt_scene *s, uint64_t seed)
{
    rt_rng rng = rt_rng_for_stream(seed, RT_STREAM_SCENE);
    uint32_t chk, ground;
    int st = checker(s, 0.32, rt_v3(.2, .3, .1), rt_v3(.9, .9, .9), &chk);
    if (!st)
        st = textured(s, chk, &ground);
    if (!st)
        st = rt_scene_add_sphere(s, rt_v3(0, -1000, 0), 1000, ground);
    for (int a = -11; a < 11 && !st; a++)
        for (int b = -11; b < 11 && !st; b++) {
            const double choose = rt_rng_double(&rng);
            const double cz = b + 0.9 * rt_rng_double(&rng); /* z, then x: docs/DEVELOPING.md */
            const rt_vec3 c = rt_v3(a + 0.9 * rt_rng_double(&rng), 0.2, cz);
            if (!(rt_v3_len(rt_v3_sub(c, rt_v3(4, 0.2, 0))) > 0.9))
                continue;
            uint32_t m;
            if (choose < 0.8) {
                rt_vec3 al;
                al.x = rt_rng_double(&rng) * rt_rng_double(&rng);
                al.y = rt_rng_double(&rng) * rt_rng_double(&rng);
                al.z = rt_rng_double(&rng) * rt_rng_double(&rng);
                st = mat(s, rt_scene_lambertian(al), &m);
                const rt_vec3 c1 = rt_v3_add(c, rt_v3(0, rt_rng_range(&rng, 0, 0.5), 0));
                if (!st)
                    st = rt_scene_add_mover(s, c, c1, 0.2, m, NULL);
            } else if (choose < 0.95) {
                rt_vec3 al;
                al.x = rt_rng_range(&rng, 0.5, 1);
                al.y = rt_rng_range(&rng, 0.5, 1);
                al.z = rt_rng_range(&rng, 0.5, 1);
                st = rt_scene_add(s, c, 0.2, rt_scene_metal(al, rt_rng_range(&rng, 0, 0.5)));
            } else {
                st = rt_scene_add(s, c, 0.2, rt_scene_dielectric(1.5));
            }
        }
    if (!st)
        st = rt_scene_add(s, rt_v3(0, 1, 0), 1.0, rt_scene_dielectric(1.5));
    if (!st)
        st = rt_scene_add(s, rt_v3(-4, 1, 0), 1.0, rt_scene_lambertian(rt_v3(0.4, 0.2, 0.1)));
    if (!st)
        st = rt_scene_add(s, rt_v3(4, 1, 0), 1.0, rt_scene_metal(rt_v3(0.7, 0.6, 0.5), 0.0));
    camera(s, rt_v3(13, 2, 3), rt_v3(0, 0, 0), 20, 0.02, 10.0);
    background(s, DAYLIGHT);
    return st;
}

static int checkered_spheres(rt_scene *s)
{
    uint32_t chk, m;
    int st = checker(s, 0.8, rt_v3(.2, .3, .1), rt_v3(.9, .9, .9), &chk);
    if (!st)
        st = textured(s, chk, &m);
    if (!st)
        st = rt_scene_add_sphere(s, rt_v3(0, -10, 0), 10, m);
    if (!st)
        st = rt_scene_add_sphere(s, rt_v3(0, 10, 0), 10, m);
    camera(s, rt_v3(13, 2, 3), rt_v3(0, 0, 0), 20, 0, 0);
    background(s, DAYLIGHT);
    return st;
}

static int earth(rt_scene *s, const rt_scene_image *img)
{
    uint32_t tex, m;
    int st = earth_texture(s, img, &tex);
    if (!st)
        st = textured(s, tex, &m);
    if (!st)
        st = rt_scene_add_sphere(s, rt_v3(0, 0, 0), 2, m);
    camera(s, rt_v3(0, 0, 12), rt_v3(0, 0, 0), 20, 0, 0);
    background(s, DAYLIGHT);
    return st;
}

/* perlin-spheres, and simple-light's two marble spheres under two lights. */
static int perlin_spheres(rt_scene *s, int lit)
{
    uint32_t tex, m, light;
    int st = marble(s, 4, &tex);
    if (!st)
        st = textured(s, tex, &m);
    if (!st)
        st = rt_scene_add_sphere(s, rt_v3(0, -1000, 0), 1000, m);
    if (!st)
        st = rt_scene_add_sphere(s, rt_v3(0, 2, 0), 2, m);
    if (!lit) {
        camera(s, rt_v3(13, 2, 3), rt_v3(0, 0, 0), 20, 0, 0);
        background(s, DAYLIGHT);
        return st;
    }
    if (!st)
        st = mat(s, rt_scene_emitter(rt_v3(4, 4, 4), 1), &light);
    if (!st)
        st = rt_scene_add_sphere(s, rt_v3(0, 7, 0), 2, light);
    if (!st)
        st = rt_scene_add_quad(s, rt_v3(3, 1, -2), rt_v3(2, 0, 0), rt_v3(0, 2, 0), light, NULL);
    camera(s, rt_v3(26, 3, 6), rt_v3(0, 2, 0), 20, 0, 0);
    background(s, rt_v3(0, 0, 0));
    return st;
}

static int quads(rt_scene *s)
{
    static const double q[5][9] = {
        {-3, -2, 5, 0, 0, -4, 0, 4, 0}, {-2, -2, 0, 4, 0, 0, 0, 4, 0}, {3, -2, 1, 0, 0, 4, 0, 4, 0},
        {-2, 3, 1, 4, 0, 0, 0, 0, 4},   {-2, -3, 5, 4, 0, 0, 0, 0, -4},
    };
    static const double col[5][3] = {{1, .2, .2}, {.2, 1, .2}, {.2, .2, 1}, {1, .5, 0}, {.2, .8, .8}};
    int st = RT_OK;
    for (int k = 0; k < 5 && !st; k++) {
        uint32_t m;
        st = mat(s, rt_scene_lambertian(rt_v3(col[k][0], col[k][1], col[k][2])), &m);
        if (!st)
            st = rt_scene_add_quad(s, rt_v3(q[k][0], q[k][1], q[k][2]), rt_v3(q[k][3], q[k][4], q[k][5]),
                                   rt_v3(q[k][6], q[k][7], q[k][8]), m, NULL);
    }
    camera(s, rt_v3(0, 0, 9), rt_v3(0, 0, 0), 80, 0, 0);
    background(s, DAYLIGHT);
    return st;
}

/* The Cornell box's walls and light; *white receives the white material.
 * smoke: cornell-smoke's larger, dimmer light and its walls' order. */
static int cornell_walls(rt_scene *s, int smoke, uint32_t *white)
{
    uint32_t red, green, light;
    int st = mat(s, rt_scene_lambertian(rt_v3(.65, .05, .05)), &red);
    if (!st)
        st = mat(s, rt_scene_lambertian(rt_v3(.73, .73, .73)), white);
    if (!st)
        st = mat(s, rt_scene_lambertian(rt_v3(.12, .45, .15)), &green);
    if (!st)
        st = mat(s, rt_scene_emitter(smoke ? rt_v3(7, 7, 7) : rt_v3(15, 15, 15), 1), &light);
    const rt_vec3 X = {555, 0, 0}, Y = {0, 555, 0}, Z = {0, 0, 555};
    if (!st)
        st = rt_scene_add_quad(s, rt_v3(555, 0, 0), Y, Z, green, NULL);
    if (!st)
        st = rt_scene_add_quad(s, rt_v3(0, 0, 0), Y, Z, red, NULL);
    if (!st && smoke)
        st = rt_scene_add_quad(s, rt_v3(113, 554, 127), rt_v3(330, 0, 0), rt_v3(0, 0, 305), light, NULL);
    if (!st && !smoke)
        st = rt_scene_add_quad(s, rt_v3(343, 554, 332), rt_v3(-130, 0, 0), rt_v3(0, 0, -105), light, NULL);
    if (!st)
        st = rt_scene_add_quad(s, rt_v3(0, 0, 0), X, Z, *white, NULL);
    if (!st) /* the ceiling */
        st = smoke ? rt_scene_add_quad(s, rt_v3(0, 555, 0), X, Z, *white, NULL)
                   : rt_scene_add_quad(s, rt_v3(555, 555, 555), rt_v3_neg(X), rt_v3_neg(Z), *white, NULL);
    if (!st)
        st = rt_scene_add_quad(s, rt_v3(0, 0, 555), X, Y, *white, NULL);
    camera(s, rt_v3(278, 278, -800), rt_v3(278, 278, 0), 40, 0, 0);
    background(s, rt_v3(0, 0, 0));
    return st;
}

/* The two boxes of the Cornell box, rotated and moved as the book's
 * instances; as media (density, colours) for cornell-smoke. */
static int cornell_boxes(rt_scene *s, uint32_t white, int smoke)
{
    const rt_xform r1 = rt_xform_rotate_y(15), t1 = rt_xform_translate(rt_v3(265, 0, 295));
    const rt_xform r2 = rt_xform_rotate_y(-18), t2 = rt_xform_translate(rt_v3(130, 0, 65));
    const rt_xform x1 = rt_xform_then(&r1, &t1), x2 = rt_xform_then(&r2, &t2);
    const rt_vec3 o = {0, 0, 0};
    if (!smoke) {
        int st = rt_scene_add_box(s, o, rt_v3(165, 330, 165), white, &x1);
        return st ? st : rt_scene_add_box(s, o, rt_v3(165, 165, 165), white, &x2);
    }
    uint32_t black, light;
    int st = mat(s, rt_scene_isotropic(rt_v3(0, 0, 0)), &black);
    if (!st)
        st = mat(s, rt_scene_isotropic(rt_v3(1, 1, 1)), &light);
    if (!st)
        st = rt_scene_add_medium_box(s, o, rt_v3(165, 330, 165), 0.01, black, &x1);
    return st ? st : rt_scene_add_medium_box(s, o, rt_v3(165, 165, 165), 0.01, light, &x2);
}

static int cornell(rt_scene *s, int smoke)
{
    uint32_t white;
    int st = cornell_walls(s, smoke, &white);
    return st ? st : cornell_boxes(s, white, smoke);
}

/* Book 3's final Cornell box: its walls as the book orders and faces
 * them, a light that emits downward only (its front face), the tall box
 * and a glass sphere in place of the short one. */
static int book3_final(rt_scene *s)
{
    uint32_t red = 0, white = 0, green = 0, light = 0, glass = 0; /* read (and dropped) on an error too */
    int st = mat(s, rt_scene_lambertian(rt_v3(.65, .05, .05)), &red);
    if (!st)
        st = mat(s, rt_scene_lambertian(rt_v3(.73, .73, .73)), &white);
    if (!st)
        st = mat(s, rt_scene_lambertian(rt_v3(.12, .45, .15)), &green);
    if (!st)
        st = mat(s, rt_scene_emitter(rt_v3(15, 15, 15), 0), &light);
    if (!st)
        st = mat(s, rt_scene_dielectric(1.5), &glass);
    const rt_vec3 X = {555, 0, 0}, Y = {0, 555, 0}, Z = {0, 0, 555};
    const struct {
        rt_vec3 q, u, v;
        uint32_t m;
    } walls[] = {
        {{555, 0, 0}, Z, Y, green},          {{0, 0, 555}, rt_v3_neg(Z), Y, red}, {{0, 555, 0}, X, Z, white},
        {{0, 0, 555}, X, rt_v3_neg(Z), white}, {{555, 0, 555}, rt_v3_neg(X), Y, white},
        {{213, 554, 227}, {130, 0, 0}, {0, 0, 105}, light}, /* u x v points down */
    };
    for (size_t i = 0; i < sizeof walls / sizeof walls[0] && !st; i++)
        st = rt_scene_add_quad(s, walls[i].q, walls[i].u, walls[i].v, walls[i].m, NULL);
    const rt_xform r1 = rt_xform_rotate_y(15), t1 = rt_xform_translate(rt_v3(265, 0, 295));
    const rt_xform x1 = rt_xform_then(&r1, &t1);
    if (!st)
        st = rt_scene_add_box(s, rt_v3(0, 0, 0), rt_v3(165, 330, 165), white, &x1);
    if (!st)
        st = rt_scene_add_sphere(s, rt_v3(190, 90, 190), 90, glass);
    camera(s, rt_v3(278, 278, -800), rt_v3(278, 278, 0), 40, 0, 0);
    background(s, rt_v3(0, 0, 0));
    return st;
}

/* The final scene: 20 x 20 ground boxes of random heights, a light, a
 * moving sphere, glass and metal, a glass ball filled with blue fog, a thin
 * fog around everything, the earth, a marble sphere and 1000 small white
 * spheres rotated and moved as one instance. */
static int final_objects(rt_scene *s, rt_rng *rng, const rt_scene_image *img)
{
    uint32_t m, light, glass, tex;
    int st = mat(s, rt_scene_emitter(rt_v3(7, 7, 7), 1), &light);
    if (!st)
        st = rt_scene_add_quad(s, rt_v3(123, 554, 147), rt_v3(300, 0, 0), rt_v3(0, 0, 265), light, NULL);
    if (!st)
        st = mat(s, rt_scene_lambertian(rt_v3(0.7, 0.3, 0.1)), &m);
    if (!st)
        st = rt_scene_add_mover(s, rt_v3(400, 400, 200), rt_v3(430, 400, 200), 50, m, NULL);
    if (!st)
        st = mat(s, rt_scene_dielectric(1.5), &glass);
    if (!st)
        st = rt_scene_add_sphere(s, rt_v3(260, 150, 45), 50, glass);
    if (!st)
        st = rt_scene_add(s, rt_v3(0, 150, 145), 50, rt_scene_metal(rt_v3(0.8, 0.8, 0.9), 1.0));
    if (!st) /* the blue ball: glass, the fog inside */
        st = rt_scene_add_sphere(s, rt_v3(360, 150, 145), 70, glass);
    if (!st)
        st = mat(s, rt_scene_isotropic(rt_v3(0.2, 0.4, 0.9)), &m);
    if (!st)
        st = rt_scene_add_medium_sphere(s, rt_v3(360, 150, 145), 70, 0.2, m);
    if (!st)
        st = mat(s, rt_scene_isotropic(rt_v3(1, 1, 1)), &m);
    if (!st)
        st = rt_scene_add_medium_sphere(s, rt_v3(0, 0, 0), 5000, 0.0001, m);
    if (!st)
        st = earth_texture(s, img, &tex);
    if (!st)
        st = textured(s, tex, &m);
    if (!st)
        st = rt_scene_add_sphere(s, rt_v3(400, 200, 400), 100, m);
    if (!st)
        st = marble(s, 0.1, &tex);
    if (!st)
        st = textured(s, tex, &m);
    if (!st)
        st = rt_scene_add_sphere(s, rt_v3(220, 280, 300), 80, m);
    const rt_xform r = rt_xform_rotate_y(15), t = rt_xform_translate(rt_v3(-100, 270, 395));
    const rt_xform x = rt_xform_then(&r, &t);
    if (!st)
        st = mat(s, rt_scene_lambertian(rt_v3(.73, .73, .73)), &m);
    for (int j = 0; j < 1000 && !st; j++) {
        rt_vec3 c;
        c.x = rt_rng_range(rng, 0, 165);
        c.y = rt_rng_range(rng, 0, 165);
        c.z = rt_rng_range(rng, 0, 165);
        st = rt_scene_add_sphere_x(s, c, 10, m, &x);
    }
    return st;
}

static int book2_final(rt_scene *s, uint64_t seed, const rt_scene_image *img)
{
    rt_rng rng = rt_rng_for_stream(seed, RT_STREAM_SCENE);
    uint32_t ground;
    int st = mat(s, rt_scene_lambertian(rt_v3(0.48, 0.83, 0.53)), &ground);
    for (int i = 0; i < 20 && !st; i++)
        for (int j = 0; j < 20 && !st; j++) {
            const double w = 100.0, x0 = -1000.0 + i * w, z0 = -1000.0 + j * w;
            st = rt_scene_add_box(s, rt_v3(x0, 0, z0), rt_v3(x0 + w, rt_rng_range(&rng, 1, 101), z0 + w), ground,
                                  NULL);
        }
    if (!st)
        st = final_objects(s, &rng, img);
    camera(s, rt_v3(478, 278, -600), rt_v3(278, 278, 0), 40, 0, 0);
    background(s, rt_v3(0, 0, 0));
    return st;
}

int rt_scenes_book2_build(rt_scene *s, const char *name, uint64_t seed, const rt_scene_image *img)
{
    int st;
    rt_scene_init(s);
    s->tex.noise_seed = seed;
    if (!strcmp(name, "bouncing-spheres"))
        st = bouncing_spheres(s, seed);
    else if (!strcmp(name, "checkered-spheres"))
        st = checkered_spheres(s);
    else if (!strcmp(name, "earth"))
        st = earth(s, img);
    else if (!strcmp(name, "perlin-spheres"))
        st = perlin_spheres(s, 0);
    else if (!strcmp(name, "quads"))
        st = quads(s);
    else if (!strcmp(name, "simple-light"))
        st = perlin_spheres(s, 1);
    else if (!strcmp(name, "cornell-box"))
        st = cornell(s, 0);
    else if (!strcmp(name, "cornell-smoke"))
        st = cornell(s, 1);
    else if (!strcmp(name, "book3-final"))
        st = book3_final(s);
    else if (!strcmp(name, "book2-final"))
        st = book2_final(s, seed, img);
    else
        st = RT_EINVAL;
    if (st)
        rt_scene_free(s);
    return st;
}
