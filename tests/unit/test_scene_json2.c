/* test_scene_json2.c - scene files of version 2 (book 2's content): a
 * hand-written file with groups and instances is the named scene, every
 * kind of object and texture round-trips through a dump, and bad input
 * (a degenerate quad, a negative density, an open boundary, an instance
 * of nothing, unknown references, a missing image) is one clear line. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io_internal.h"
#include "core_internal.h"
#include "check.h"
#include "scene_json.h"
#include "scenes.h"
#include "status.h"

#define HEAD "{\"version\": 2, \"camera\": {\"lookfrom\": [0, 0, 9], \"lookat\": [0, 0, 0]}, "
#define ISO "\"materials\": [{\"name\": \"fog\", \"type\": \"isotropic\", \"albedo\": [1, 1, 1]}, " \
            "{\"name\": \"white\", \"type\": \"lambertian\", \"albedo\": [0.7, 0.7, 0.7]}]"
#define BOX "{\"min\": [0, 0, 0], \"max\": [1, 2, 3], \"material\": \"white\"}"
/* The six faces of the unit cube, facing out; FACES5 leaves the top open. */
#define FACES5 "{\"q\": [0, 0, 1], \"u\": [1, 0, 0], \"v\": [0, 1, 0]}, {\"q\": [1, 0, 1], \"u\": [0, 0, -1], "  \
               "\"v\": [0, 1, 0]}, {\"q\": [1, 0, 0], \"u\": [-1, 0, 0], \"v\": [0, 1, 0]}, "                  \
               "{\"q\": [0, 0, 0], \"u\": [0, 0, 1], \"v\": [0, 1, 0]}, {\"q\": [0, 0, 0], \"u\": [1, 0, 0], " \
               "\"v\": [0, 0, 1]}"
#define TOP "{\"q\": [0, 1, 1], \"u\": [1, 0, 0], \"v\": [0, 0, -1]}"

static int parse(rt_scene *s, const char *text, char *err, size_t errlen)
{
    return rt_scene_json_parse(s, text, strlen(text), "s.json", NULL, NULL, err, errlen);
}

static void expect_error(const char *text, const char *want)
{
    rt_scene s;
    char err[512] = "";
    CHECK_EQ_INT(parse(&s, text, err, sizeof err), RT_EFORMAT);
    CHECK_HAS(err, want);
    CHECK(strchr(err, '\n') == NULL);
    CHECK_EQ_INT(s.shapes.quads.n + s.n_spheres + s.media.media.n, 0);
}

static void round_trip(const char *text)
{
    rt_scene a, b;
    char err[512] = "", *t1 = NULL, *t2 = NULL;
    size_t n1 = 0, n2 = 0;
    CHECK_EQ_INT(parse(&a, text, err, sizeof err), RT_OK);
    if (err[0])
        fprintf(stderr, "%s\n", err);
    CHECK_EQ_INT(rt_scene_json_format(&a, NULL, &t1, &n1), RT_OK);
    CHECK_EQ_INT(rt_scene_json_parse(&b, t1, n1, "dump.json", NULL, NULL, err, sizeof err), RT_OK);
    CHECK_EQ_INT(rt_scene_json_format(&b, NULL, &t2, &n2), RT_OK);
    CHECK(n1 == n2 && !memcmp(t1, t2, n1));
    CHECK_EQ_U64(rt_scene_hash(&b), rt_scene_hash(&a));
    free(t1);
    free(t2);
    rt_scene_free(&a);
    rt_scene_free(&b);
}

int main(int argc, char **argv)
{
    rt_scene s, named;
    char err[512] = "";

    /* The committed Cornell box (groups, instances, names) is the named scene. */
    if (argc > 1) {
        char path[1024];
        snprintf(path, sizeof path, "%s/scenes/cornell-box.json", argv[1]);
        CHECK_EQ_INT(rt_scene_json_load(&s, path, NULL, err, sizeof err), RT_OK);
        CHECK_EQ_INT(rt_scene_build_named(&named, "cornell-box", 42, 11, NULL), RT_OK);
        CHECK_EQ_U64(rt_scene_hash(&s), rt_scene_hash(&named));
        CHECK_EQ_INT(s.shapes.quads.n, 18);
        rt_scene_free(&s);
        rt_scene_free(&named);
    }

    /* Every kind, and what instances make of spheres (frames). */
    round_trip(HEAD "\"background\": {\"color\": [0.1, 0.2, 0.3]}, \"noise_seed\": \"18446744073709551615\", "
                    "\"textures\": [{\"name\": \"a\", \"type\": \"solid\", \"color\": [1, 0, 0]}, {\"type\": \"solid\", "
                    "\"color\": [0, 1, 0]}, {\"type\": \"checker\", \"scale\": 0.5, \"even\": \"a\", \"odd\": 1}, "
                    "{\"type\": \"turbulence\", \"scale\": 4}, {\"type\": \"marble\", \"scale\": 0.1, \"color\": [1, 1, 0]}, "
                    "{\"type\": \"noise\", \"scale\": 2}], "
                    "\"materials\": [{\"type\": \"lambertian\", \"texture\": 2}, {\"type\": \"emitter\", \"emit\": [15, 15, 15], "
                    "\"two_sided\": false}, {\"type\": \"isotropic\", \"texture\": 4}, {\"type\": \"metal\", \"albedo\": [1, 1, 1]}], "
                    "\"spheres\": [{\"center\": [0, 0, 0], \"radius\": 1, \"material\": 0}], "
                    "\"moving_spheres\": [{\"center0\": [0, 1, 0], \"center1\": [0, 2, 0], \"radius\": 0.5, \"material\": 3}], "
                    "\"quads\": [{\"q\": [0, 0, 0], \"u\": [1, 0, 0], \"v\": [0, 1, 0], \"material\": 1}], "
                    "\"boxes\": [{\"min\": [0, 0, 0], \"max\": [1, 1, 1], \"material\": {\"type\": \"dielectric\", \"ior\": 1.5}}], "
                    "\"media\": [{\"sphere\": {\"center\": [0, 0, 0], \"radius\": 3}, \"density\": 0.5, \"material\": 2}, "
                    "{\"box\": {\"min\": [0, 0, 0], \"max\": [1, 1, 1]}, \"density\": 2, \"material\": 2}, "
                    "{\"hull\": [" FACES5 ", " TOP "], \"density\": 1, \"material\": 2}], "
                    "\"groups\": {\"g\": {\"spheres\": [{\"center\": [1, 0, 0], \"radius\": 0.2, \"material\": 0}], "
                    "\"media\": [{\"box\": {\"min\": [0, 0, 0], \"max\": [1, 1, 1]}, \"density\": 2, \"material\": 2}], "
                    "\"moving_spheres\": [{\"center0\": [0, 1, 0], \"center1\": [0, 2, 0], \"radius\": 0.5, \"material\": 3}]}}, "
                    "\"instances\": [{\"group\": \"g\", \"rotate_y\": 30, \"translate\": [1, 2, 3]}, "
                    "{\"objects\": {\"instances\": [{\"group\": \"g\", \"rotate_y\": -10}]}, \"translate\": [5, 0, 0]}]}");
    CHECK_EQ_INT(parse(&s, HEAD "\"groups\": {\"g\": {\"spheres\": [{\"center\": [1, 0, 0], \"radius\": 0.2, "
                              "\"material\": {\"type\": \"metal\", \"albedo\": [1, 1, 1]}}]}}, "
                              "\"instances\": [{\"group\": \"g\", \"rotate_y\": 90, \"translate\": [0, 0, 5]}]}",
                       err, sizeof err),
                 RT_OK);
    CHECK_EQ_INT(s.shapes.frames.n, 1);
    CHECK_NEAR(s.spheres[0].center.x, 0.0, 1e-12); /* rotate_y(90) takes +x to -z, then the translation */
    CHECK_NEAR(s.spheres[0].center.z, 4.0, 1e-12);
    rt_scene_free(&s);

    /* Bad input: one line naming the field. */
    expect_error(HEAD ISO ", \"quads\": [{\"q\": [0, 0, 0], \"u\": [1, 0, 0], \"v\": [2, 0, 0], \"material\": 1}]}",
                 "s.json: quads[0]: degenerate quad: u and v span no area (u x v = 0)");
    expect_error(HEAD ISO ", \"boxes\": [{\"min\": [0, 0, 0], \"max\": [1, 0, 1], \"material\": 1}]}",
                 "s.json: boxes[0]: degenerate box: min must be below max on every axis");
    expect_error(HEAD ISO ", \"media\": [{\"sphere\": {\"center\": [0, 0, 0], \"radius\": 1}, \"density\": -1, "
                          "\"material\": \"fog\"}]}",
                 "s.json: media[0].density: -1 is out of range (0, 1e+12]");
    expect_error(HEAD ISO ", \"media\": [{\"hull\": [" FACES5 "], \"density\": 1, \"material\": \"fog\"}]}",
                 "s.json: media[0].hull: the boundary is open (an edge of a quad is no other quad's edge)");
    expect_error(HEAD ISO ", \"media\": [{\"box\": {\"min\": [0, 0, 0], \"max\": [1, 1, 1]}, \"density\": 1, "
                          "\"material\": \"white\"}]}",
                 "s.json: media[0]: a medium's material must be isotropic");
    expect_error(HEAD ISO ", \"media\": [{\"density\": 1, \"material\": 0}]}",
                 "s.json: media[0]: give the boundary as one of sphere, box, hull");
    expect_error(HEAD ISO ", \"groups\": {\"g\": {}}, \"instances\": [{\"group\": \"g\"}]}",
                 "s.json: instances[0].group: instance of nothing (no objects)");
    expect_error(HEAD ISO ", \"instances\": [{\"objects\": {\"quads\": []}}]}",
                 "s.json: instances[0].objects: instance of nothing (no objects)");
    expect_error(HEAD ISO ", \"instances\": [{\"group\": \"nope\"}]}", "s.json: instances[0].group: no group named 'nope'");
    /* groups as an array (its items have no names): found by fuzzing, it crashed the loader */
    expect_error(HEAD ISO ", \"groups\": [{\"quads\": []}], \"instances\": [{\"group\": \"g\"}]}",
                 "s.json: groups: expected an object");
    expect_error(HEAD ISO ", \"groups\": {\"g\": {\"instances\": [{\"group\": \"g\"}]}}, \"instances\": [{\"group\": \"g\"}]}",
                 "instances nested deeper than 16 (a group that contains itself?)");
    expect_error(HEAD ISO ", \"boxes\": [" BOX "], \"textures\": [{\"type\": \"checker\", \"scale\": 1, \"even\": 0, "
                          "\"odd\": 0}]}",
                 "s.json: textures[0].even: 0 is not an index into textures (there are none)");
    expect_error(HEAD "\"materials\": [{\"type\": \"lambertian\", \"texture\": \"wood\"}]}",
                 "s.json: materials[0].texture: no textures named 'wood'");
    expect_error(HEAD "\"textures\": [{\"type\": \"solid\", \"color\": [1, 1, 1]}], \"materials\": [{\"type\": "
                      "\"lambertian\", \"texture\": 0, \"albedo\": [1, 1, 1]}]}",
                 "s.json: materials[0]: give albedo or texture, not both");
    expect_error(HEAD ISO ", \"quads\": [{\"q\": [0, 0, 0], \"u\": [1, 0, 0], \"v\": [0, 1, 0], \"material\": \"wood\"}]}",
                 "s.json: quads[0].material: no materials named 'wood'");
    expect_error(HEAD "\"textures\": [{\"type\": \"image\", \"path\": \"earth.jpg\"}]}",
                 "s.json: textures[0].path: image textures are read from files only");
    expect_error(HEAD "\"materials\": [{\"type\": \"emitter\", \"emit\": [1, 1, 1], \"two_sided\": 1}]}",
                 "s.json: materials[0].two_sided: expected true or false");
    expect_error(HEAD ISO ", \"frames\": [[[1, 0, 0], [0, 1, 0], [0, 0, 1]]], \"groups\": {\"g\": {\"spheres\": "
                          "[{\"center\": [0, 0, 0], \"radius\": 1, \"material\": 1, \"frame\": 0}]}}, "
                          "\"instances\": [{\"group\": \"g\"}]}",
                 "frame: only at the top level (an instance makes its own frames)");
    expect_error("{\"camera\": {\"lookfrom\": [0, 0, 9], \"lookat\": [0, 0, 0]}, \"spheres\": [], \"quads\": []}",
                 "s.json: quads: unknown field (expected one of: version, camera, camera_keys, background, materials, spheres)");

    /* Image files: missing is RT_ENOFILE naming the file; a dump refers to it relative to the dump. */
    char dir[] = "/tmp/rt-json2-XXXXXX", path[256];
    CHECK(mkdtemp(dir) != NULL);
    snprintf(path, sizeof path, "%s/s.json", dir);
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    if (f) {
        fputs(HEAD "\"textures\": [{\"type\": \"image\", \"path\": \"img/e.jpg\"}]}", f);
        fclose(f);
    }
    CHECK_EQ_INT(rt_scene_json_load(&s, path, NULL, err, sizeof err), RT_ENOFILE);
    CHECK_HAS(err, "s.json: textures[0].path: ");
    CHECK_HAS(err, "/img/e.jpg: no such file");
    char cmd[512];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    CHECK_EQ_INT(system(cmd), 0);
    CHECK_DONE();
}
