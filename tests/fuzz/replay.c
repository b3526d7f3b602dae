/* replay.c - regression test: every file of a fuzz corpus and every
 * crasher found so far goes through the loader (built normally, no
 * libFuzzer) and must keep its check's properties: fuzz_scene_json_check's,
 * or fuzz_texture_image_check's when built with FUZZ_TEXTURE. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fileio.h"
#ifdef FUZZ_TEXTURE
#include "texture_image_check.h"
#define FUZZ_CHECK fuzz_texture_image_check
#else
#include "scene_json_check.h"
#define FUZZ_CHECK fuzz_scene_json_check
#endif
#include "status.h"

static int passed, failed;

static void run_file(const char *path)
{
    char *buf = NULL;
    size_t len = 0;
    if (rt_file_read_all(path, (size_t)-1 / 2, &buf, &len) != RT_OK) {
        printf("FAIL: %s: cannot read\n", path);
        failed++;
    } else {
        const char *bad = FUZZ_CHECK((const uint8_t *)buf, len);
        if (bad) {
            printf("FAIL: %s: %s\n", path, bad);
            failed++;
        } else {
            passed++;
        }
    }
    free(buf);
}

int main(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        DIR *d = opendir(argv[i]);
        if (!d) {
            printf("FAIL: %s: cannot open the directory\n", argv[i]);
            failed++;
            continue;
        }
        struct dirent *e;
        while ((e = readdir(d)) != NULL) {
            if (e->d_name[0] == '.' || !strcmp(e->d_name, "README"))
                continue;
            char path[4096];
            snprintf(path, sizeof path, "%s/%s", argv[i], e->d_name);
            run_file(path);
        }
        closedir(d);
    }
    printf("%d passed, %d failed\n", passed, failed);
    return failed || !passed ? 1 : 0;
}
