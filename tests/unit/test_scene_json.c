/* test_scene_json.c - scene files: dump -> load -> dump is byte-identical
 * and a loaded dump is the very scene (same serialized bytes) for every
 * named scene; exact numbers; defaults and the v4 lens; every error names
 * the file, the field and the problem; dumps are atomic. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io_internal.h"
#include "core_internal.h"
#include "check.h"
#include "scene_json.h"
#include "scenes.h"
#include "status.h"

#define CAM "\"camera\": {\"lookfrom\": [0, 0, 0], \"lookat\": [0, 0, -1]}"
#define SPH(mat) "{\"center\": [0, 0, -1], \"radius\": 0.5, \"material\": " mat "}"
#define LAMB "{\"type\": \"lambertian\", \"albedo\": [0.5, 0.5, 0.5]}"

static int parse(rt_scene *s, const char *text, char *err, size_t errlen)
{
    return rt_scene_json_parse(s, text, strlen(text), "scene.json", NULL, NULL, err, errlen);
}

/* A valid file must load; a broken one must fail with exactly `want`. */
static void expect_error(const char *text, const char *want)
{
    rt_scene s;
    char err[512] = "";
    int st = parse(&s, text, err, sizeof err);
    CHECK_EQ_INT(st, RT_EFORMAT);
    if (strcmp(err, want) != 0) {
        check_fail++;
        fprintf(stderr, "error message\n  got:  %s\n  want: %s\n  for:  %s\n", err, want, text);
    } else {
        check_pass++;
    }
    CHECK_EQ_INT(s.n_spheres, 0);
}

/* dump -> load -> dump: identical text, identical serialized scene. */
static void round_trip(const rt_scene *a, const char *label)
{
    char *t1 = NULL, *t2 = NULL, err[512] = "";
    size_t n1 = 0, n2 = 0;
    rt_scene b;
    CHECK_EQ_INT(rt_scene_json_format(a, NULL, &t1, &n1), RT_OK);
    int st = rt_scene_json_parse(&b, t1, n1, label, NULL, NULL, err, sizeof err);
    CHECK_EQ_INT(st, RT_OK);
    if (st)
        fprintf(stderr, "%s: %s\n", label, err);
    CHECK_EQ_INT(rt_scene_json_format(&b, NULL, &t2, &n2), RT_OK);
    CHECK_EQ_INT(n1, n2);
    CHECK(n1 == n2 && memcmp(t1, t2, n1) == 0);
    CHECK_EQ_U64(rt_scene_hash(&b), rt_scene_hash(a));
    CHECK_EQ_INT(strlen(t1), n1);
    rt_scene_free(&b);
    free(t1);
    free(t2);
}

int main(int argc, char **argv)
{
    rt_scene s;
    char err[512];

    for (unsigned i = 0; i < rt_scenes_count(); i++) {
        if (rt_scenes_info(i)->needs_earth) /* images need files: e2e_book2 dumps these */
            continue;
        CHECK_EQ_INT(rt_scene_build_named(&s, rt_scenes_info(i)->name, 42, 11, NULL), RT_OK);
        round_trip(&s, rt_scenes_info(i)->name);
        rt_scene_free(&s);
    }
    CHECK_EQ_INT(rt_scene_build_final(&s, 9, 40), RT_OK); /* thousands of spheres */
    round_trip(&s, "final 40");
    rt_scene_free(&s);

    /* Awkward doubles survive exactly: shortest round-trip digits. */
    rt_scene_init(&s);
    s.camera.lookfrom = rt_v3(0.1 + 0.2, -0.0, 1e-300);
    s.camera.lookat = rt_v3(5e-324, 123456789012.5, -1.0 / 3.0);
    s.camera.vfov_deg = 179.99999999999997;
    s.sky_top = rt_v3(0.7, 1e-7, 999.9999999999999);
    CHECK_EQ_INT(rt_scene_add(&s, rt_v3(2.5e-10, 1e12, -1e12), -1e-9, rt_scene_metal(rt_v3(1, 0, 0.3), 0.25)),
                 RT_OK);
    round_trip(&s, "awkward numbers");
    char *text;
    size_t len;
    CHECK_EQ_INT(rt_scene_json_format(&s, NULL, &text, &len), RT_OK);
    CHECK(strstr(text, "\"vfov\": 179.99999999999997,") != NULL);
    CHECK(strstr(text, "\"lookfrom\": [0.30000000000000004, -0, 1e-300]") != NULL);
    free(text);
    rt_scene_free(&s);

    /* The committed example loads (argv[1] = source directory). */
    if (argc > 1) {
        char path[1024];
        snprintf(path, sizeof path, "%s/scenes/example.json", argv[1]);
        int st = rt_scene_json_load(&s, path, NULL, err, sizeof err);
        CHECK_EQ_INT(st, RT_OK);
        if (st)
            fprintf(stderr, "%s\n", err);
        CHECK(s.n_spheres > 3);
        rt_scene_free(&s);
    }

    /* Defaults: vup +y, vfov 90, pinhole, focus at lookat, the book's sky. */
    CHECK_EQ_INT(parse(&s, "{" CAM ", \"spheres\": []}", err, sizeof err), RT_OK);
    CHECK_NEAR(s.camera.vup.y, 1, 0);
    CHECK_NEAR(s.camera.vfov_deg, 90, 0);
    CHECK_NEAR(s.camera.aperture, 0, 0);
    CHECK_NEAR(s.sky_top.y, 0.7, 0);
    CHECK_EQ_INT(s.n_spheres, 0);
    rt_scene_free(&s);
    /* focus distance defaults to |lookfrom - lookat| (3 here, not the 1 that
     * rt_scene_init would leave) */
    CHECK_EQ_INT(parse(&s, "{\"camera\": {\"lookfrom\": [0, 0, 0], \"lookat\": [0, 0, -3]}, \"spheres\": []}", err,
                       sizeof err),
                 RT_OK);
    CHECK_NEAR(s.camera.focus_dist, 3, 1e-12);
    rt_scene_free(&s);
    /* Book v4's lens: aperture = 2 focus_dist tan(angle / 2). */
    const char *v4 = "{\"camera\": {\"lookfrom\": [13, 2, 3], \"lookat\": [0, 0, 0], \"defocus_angle\": 0.6, "
                     "\"focus_dist\": 10.0}, \"spheres\": []}";
    CHECK_EQ_INT(parse(&s, v4, err, sizeof err), RT_OK);
    CHECK_NEAR(s.camera.aperture, 2 * 10.0 * tan(0.3 * 3.14159265358979323846 / 180), 1e-15);
    CHECK_NEAR(s.camera.focus_dist, 10, 0);
    rt_scene_free(&s);
    /* Inline materials come after the table; indices refer to the table. */
    const char *mixed = "{" CAM ", \"materials\": [" LAMB ", {\"type\": \"dielectric\", \"ior\": 1.33}], "
                        "\"spheres\": [" SPH("1") ", " SPH("{\"type\": \"metal\", \"albedo\": [1, 1, 1]}") ", " SPH(
                            "0") "], \"background\": {\"top\": [0, 0, 0]}, \"version\": 1}";
    CHECK_EQ_INT(parse(&s, mixed, err, sizeof err), RT_OK);
    CHECK_EQ_INT(s.n_materials, 3);
    CHECK_EQ_INT(s.spheres[0].material, 1);
    CHECK_EQ_INT(s.spheres[1].material, 2);
    CHECK_EQ_INT(s.materials[2].kind, RT_MAT_METAL);
    CHECK_NEAR(s.materials[2].fuzz, 0, 0);
    CHECK_EQ_INT(s.spheres[2].material, 0);
    CHECK_NEAR(s.sky_top.x, 0, 0);
    CHECK_NEAR(s.sky_bottom.x, 1, 0);
    rt_scene_free(&s);

    /* Errors: file, field path, problem. */
    expect_error("{" CAM ", \"spheres\": [" SPH("{" "\"type\": \"lambertian\", \"albedo\": [1, 1, 1]}") ", " SPH(
                     "{\"type\": \"metal\", \"albedo\": [1, 1, 1]}") ", " SPH("{\"type\": \"dielectric\", "
                                                                              "\"ior\": 1.5}") ", "
                 "{\"center\": [0, 0, -1], \"radius\": \"big\", \"material\": 0}]}",
                 "scene.json: spheres[3].radius: expected a number");
    expect_error("", "scene.json: line 1, column 1: empty file");
    /* cJSON points just past the character it stopped at (the comma here). */
    expect_error("{\n  \"camera\": {,\n}", "scene.json: line 2, column 15: invalid JSON");
    expect_error("{" CAM ", \"spheres\": []} []", "scene.json: line 1, column 74: unexpected text after the JSON value");
    expect_error("[]", "scene.json: expected a JSON object at the top level");
    expect_error("{\"spheres\": []}", "scene.json: camera: missing");
    expect_error("{" CAM "}", "scene.json: spheres: missing");
    expect_error("{" CAM ", \"spheres\": {}}", "scene.json: spheres: expected an array");
    expect_error("{" CAM ", \"spheres\": [], \"lights\": []}",
                 "scene.json: lights: unknown field (expected one of: version, camera, camera_keys, background, materials, "
                 "spheres)");
    expect_error("{" CAM ", \"spheres\": [], \"spheres\": []}", "scene.json: spheres: duplicate field");
    expect_error("{" CAM ", \"spheres\": [], \"version\": 3}",
                 "scene.json: version: this program reads versions 1 and 2");
    expect_error("{\"camera\": [], \"spheres\": []}", "scene.json: camera: expected an object");
    expect_error("{\"camera\": {\"lookat\": [0, 0, -1]}, \"spheres\": []}", "scene.json: camera.lookfrom: missing");
    expect_error("{\"camera\": {\"lookfrom\": [0, 0], \"lookat\": [0, 0, -1]}, \"spheres\": []}",
                 "scene.json: camera.lookfrom: expected an array of 3 numbers");
    expect_error("{\"camera\": {\"lookfrom\": [0, null, 0], \"lookat\": [0, 0, -1]}, \"spheres\": []}",
                 "scene.json: camera.lookfrom[1]: expected a number");
    expect_error("{\"camera\": {\"lookfrom\": [0, 0, 1e999], \"lookat\": [0, 0, -1]}, \"spheres\": []}",
                 "scene.json: camera.lookfrom[2]: expected a finite number");
    expect_error("{\"camera\": {\"lookfrom\": [0, 0, 1e13], \"lookat\": [0, 0, -1]}, \"spheres\": []}",
                 "scene.json: camera.lookfrom[2]: 10000000000000 is out of range [-1e+12, 1e+12]");
    expect_error("{\"camera\": {\"lookfrom\": [1, 2, 3], \"lookat\": [1, 2, 3]}, \"spheres\": []}",
                 "scene.json: camera.lookat: equals camera.lookfrom (no view direction)");
    expect_error("{\"camera\": {\"lookfrom\": [0, 0, 0], \"lookat\": [0, 5, 0]}, \"spheres\": []}",
                 "scene.json: camera.vup: zero or parallel to the view direction (lookat - lookfrom)");
    expect_error("{\"camera\": {\"lookfrom\": [0, 0, 0], \"lookat\": [0, 0, -1], \"vfov\": 0}, \"spheres\": []}",
                 "scene.json: camera.vfov: 0 is out of range (0, 180)");
    expect_error("{\"camera\": {\"lookfrom\": [0, 0, 0], \"lookat\": [0, 0, -1], \"aperture\": -1}, \"spheres\": []}",
                 "scene.json: camera.aperture: -1 is out of range [0, 1e+12]");
    expect_error("{\"camera\": {\"lookfrom\": [0, 0, 0], \"lookat\": [0, 0, -1], \"focus_dist\": 0}, \"spheres\": []}",
                 "scene.json: camera.focus_dist: 0 is out of range (0, 1e+12]");
    expect_error("{\"camera\": {\"lookfrom\": [0, 0, 0], \"lookat\": [0, 0, -1], \"aperture\": 1, \"defocus_angle\": "
                 "1}, \"spheres\": []}",
                 "scene.json: camera: give the lens as aperture or as defocus_angle, not both");
    expect_error("{\"camera\": {\"lookfrom\": [0, 0, 0], \"lookat\": [0, 0, -1], \"defocus_angle\": 180}, "
                 "\"spheres\": []}",
                 "scene.json: camera.defocus_angle: 180 is out of range [0, 180)");
    expect_error("{\"camera\": {\"lookfrom\": [0, 0, 0], \"lookat\": [0, 0, -1], \"fov\": 40}, \"spheres\": []}",
                 "scene.json: camera.fov: unknown field (expected one of: lookfrom, lookat, vup, vfov, aperture, "
                 "defocus_angle, focus_dist)");
    expect_error("{" CAM ", \"background\": {\"top\": [0, 0, -1]}, \"spheres\": []}",
                 "scene.json: background.top[2]: -1 is out of range [0, 1000]");
    expect_error("{" CAM ", \"spheres\": [{\"center\": [0, 0, -1], \"radius\": 0, \"material\": " LAMB "}]}",
                 "scene.json: spheres[0].radius: must not be 0 (a negative radius makes a hollow sphere)");
    expect_error("{" CAM ", \"spheres\": [{\"center\": [0, 0, -1], \"material\": " LAMB "}]}",
                 "scene.json: spheres[0].radius: missing");
    expect_error("{" CAM ", \"spheres\": [" SPH("0") "]}",
                 "scene.json: spheres[0].material: 0 is not an index into materials (there are none)");
    expect_error("{" CAM ", \"materials\": [" LAMB "], \"spheres\": [" SPH("1") "]}",
                 "scene.json: spheres[0].material: 1 is not an index into materials (0 to 0)");
    expect_error("{" CAM ", \"materials\": [" LAMB "], \"spheres\": [" SPH("0.5") "]}",
                 "scene.json: spheres[0].material: 0.5 is not an index into materials (0 to 0)");
    expect_error("{" CAM ", \"spheres\": [" SPH("\"glass\"") "]}",
                 "scene.json: spheres[0].material: expected an index into materials or a material object");
    expect_error("{" CAM ", \"spheres\": [" SPH("{\"albedo\": [1, 1, 1]}") "]}",
                 "scene.json: spheres[0].material.type: missing");
    expect_error("{" CAM ", \"spheres\": [" SPH("{\"type\": \"glass\"}") "]}",
                 "scene.json: spheres[0].material.type: 'glass' is not one of lambertian, metal, dielectric");
    expect_error("{" CAM ", \"materials\": [{\"type\": \"metal\", \"albedo\": [1, 1, 1], \"fuzz\": 1.5}], "
                 "\"spheres\": []}",
                 "scene.json: materials[0].fuzz: 1.5 is out of range [0, 1]");
    expect_error("{" CAM ", \"materials\": [{\"type\": \"lambertian\", \"albedo\": [1, 1.01, 1]}], \"spheres\": []}",
                 "scene.json: materials[0].albedo[1]: 1.01 is out of range [0, 1]");
    expect_error("{" CAM ", \"materials\": [{\"type\": \"lambertian\", \"albedo\": [1, 1, 1], \"fuzz\": 0}], "
                 "\"spheres\": []}",
                 "scene.json: materials[0].fuzz: unknown field (expected one of: type, name, albedo)");
    expect_error("{" CAM ", \"materials\": [{\"type\": \"dielectric\", \"ior\": 0}], \"spheres\": []}",
                 "scene.json: materials[0].ior: 0 is out of range (0, 100]");
    expect_error("{" CAM ", \"materials\": [{\"type\": \"dielectric\"}], \"spheres\": []}",
                 "scene.json: materials[0].ior: missing");
    expect_error("{" CAM ", \"spheres\": [], \"\\u0001\\u00e9x\": 1}",
                 "scene.json: ???x: unknown field (expected one of: version, camera, camera_keys, background, materials, "
                 "spheres)");

    /* Files: unreadable ones are RT_EIO with the reason; dumps are atomic. */
    CHECK_EQ_INT(rt_scene_json_load(&s, "/nonexistent/scene.json", NULL, err, sizeof err), RT_EIO);
    CHECK(!strcmp(err, "/nonexistent/scene.json: cannot read: No such file or directory"));
    CHECK_EQ_INT(rt_scene_json_load(&s, "/", NULL, err, sizeof err), RT_EIO);
    CHECK(!strcmp(err, "/: cannot read: Is a directory"));
    char dir[] = "/tmp/rt-json-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256];
    snprintf(path, sizeof path, "%s/missing/x.json", dir);
    CHECK_EQ_INT(rt_scene_build_named(&s, "materials", 1, 1, NULL), RT_OK);
    CHECK(rt_scene_json_dump(&s, NULL, path) != RT_OK);
    snprintf(path, sizeof path, "%s/x.json", dir);
    CHECK_EQ_INT(rt_scene_json_dump(&s, NULL, path), RT_OK);
    rt_scene back;
    CHECK_EQ_INT(rt_scene_json_load(&back, path, NULL, err, sizeof err), RT_OK);
    CHECK_EQ_U64(rt_scene_hash(&back), rt_scene_hash(&s));
    rt_scene_free(&back);
    rt_scene_free(&s);
    char cmd[512];
    snprintf(cmd, sizeof cmd, "test \"$(ls %s)\" = x.json && rm -rf %s", dir, dir);
    CHECK_EQ_INT(system(cmd), 0);
    CHECK_DONE();
}
