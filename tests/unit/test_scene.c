/* test_scene.c - final scene build determinism, and the byte format:
 * serialize -> deserialize -> serialize is byte-identical; corruption,
 * truncation and version changes are refused. */
#include <stdlib.h>
#include <string.h>

#include "core_internal.h"
#include "check.h"
#include "hash.h"
#include "scene.h"
#include "status.h"

int main(void)
{
    rt_scene a, b, c;
    CHECK_EQ_INT(rt_scene_build_final(&a, 42, 11), RT_OK);
    CHECK_EQ_INT(rt_scene_build_final(&b, 42, 11), RT_OK);
    CHECK_EQ_U64(rt_scene_hash(&a), rt_scene_hash(&b));
    /* 22 x 22 candidates minus those near the big spheres, + ground + 3. */
    CHECK(a.n_spheres > 400 && a.n_spheres <= 22 * 22 + 4);
    CHECK_NEAR(a.spheres[0].radius, 1000, 0);
    CHECK_NEAR(a.spheres[a.n_spheres - 1].center.x, 4, 0);
    CHECK_NEAR(a.camera.vfov_deg, 20, 0);
    CHECK_NEAR(a.camera.aperture, 0.1, 0);
    CHECK_NEAR(a.camera.focus_dist, 10, 0);
    /* Material mix close to 80/15/5 over a big grid. */
    rt_scene big;
    CHECK_EQ_INT(rt_scene_build_final(&big, 7, 60), RT_OK);
    int kinds[3] = {0, 0, 0};
    for (uint32_t i = 1; i + 3 < big.n_spheres; i++)
        kinds[big.materials[big.spheres[i].material].kind]++;
    double n = kinds[0] + kinds[1] + kinds[2];
    CHECK_NEAR(kinds[0] / n, 0.80, 0.02);
    CHECK_NEAR(kinds[1] / n, 0.15, 0.02);
    CHECK_NEAR(kinds[2] / n, 0.05, 0.01);
    rt_scene_free(&big);
    /* Another seed, another scene. */
    rt_scene_free(&b);
    CHECK_EQ_INT(rt_scene_build_final(&b, 43, 11), RT_OK);
    CHECK(rt_scene_hash(&a) != rt_scene_hash(&b));
    rt_scene_free(&b);

    uint8_t *buf1, *buf2;
    size_t len1, len2;
    CHECK_EQ_INT(rt_scene_serialize(&a, &buf1, &len1), RT_OK);
    CHECK_EQ_INT(rt_scene_deserialize(&c, buf1, len1), RT_OK);
    /* the bytes' hash from their checksum: the FNV-1a of all of them */
    CHECK_EQ_U64(rt_scene_bytes_hash(buf1, len1), rt_hash_bytes(RT_HASH_INIT, buf1, len1));
    CHECK_EQ_INT(rt_scene_serialize(&c, &buf2, &len2), RT_OK);
    CHECK_EQ_INT(len1, len2);
    CHECK(len1 == len2 && memcmp(buf1, buf2, len1) == 0);
    CHECK_EQ_INT(c.n_spheres, a.n_spheres);
    rt_scene_free(&c);

    /* Every single flipped byte is caught (checksum or format check). */
    int all_refused = 1;
    for (size_t i = 0; i < len1; i += 7) {
        buf1[i] ^= 0x5a;
        if (rt_scene_deserialize(&c, buf1, len1) == RT_OK) {
            all_refused = 0;
            rt_scene_free(&c);
        }
        buf1[i] ^= 0x5a;
    }
    CHECK(all_refused);
    CHECK_EQ_INT(rt_scene_deserialize(&c, buf1, len1 - 1), RT_EFORMAT);
    CHECK_EQ_INT(rt_scene_deserialize(&c, buf1, 10), RT_EFORMAT);
    buf1[8] = 99; /* version */
    CHECK_EQ_INT(rt_scene_deserialize(&c, buf1, len1), RT_EVERSION);
    free(buf1);
    free(buf2);
    rt_scene_free(&a);
    CHECK_DONE();
}
