/* test_report.c - the JSON reports: UTF-8 cleaning of every kind of bad
 * byte sequence, and --stats / --trace files whose command line holds
 * tabs, newlines, quotes, backslashes and invalid UTF-8 read back as valid
 * JSON with the exact (cleaned) strings, whole 64-bit numbers and the
 * provenance fields. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cJSON.h>

#include "check.h"
#include "report.h"
#include "rt_config.h"

#define FFFD "\xEF\xBF\xBD"

/* rt_report_utf8(in) is want; prints both when not. */
static void check_clean(const char *in, const char *want)
{
    char *got = rt_report_utf8(in);
    if (!got || strcmp(got, want))
        fprintf(stderr, "  rt_report_utf8 of '%s' gave '%s', want '%s'\n", in, got ? got : "(null)", want);
    CHECK(got && !strcmp(got, want));
    free(got);
}

/* The whole file, NUL-terminated (malloc'd). */
static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *buf = calloc(1, 1 << 20);
    size_t n = buf ? fread(buf, 1, (1 << 20) - 1, f) : 0;
    (void)n;
    fclose(f);
    return buf;
}

/* The file is valid UTF-8 and parses as JSON; returns the document. */
static cJSON *load(const char *path)
{
    char *text = slurp(path);
    CHECK(text != NULL);
    if (!text)
        return NULL;
    char *clean = rt_report_utf8(text);
    CHECK(clean && !strcmp(clean, text)); /* nothing to replace: valid UTF-8 */
    for (const char *p = text; *p; p++) /* raw control bytes only between tokens */
        if ((unsigned char)*p < 0x20 && *p != '\n' && *p != '\t') {
            fprintf(stderr, "  raw control byte %02x in %s\n", (unsigned char)*p, path);
            CHECK(0);
            break;
        }
    cJSON *doc = cJSON_Parse(text);
    if (!doc)
        fprintf(stderr, "  %s is no JSON:\n%s\n", path, text);
    CHECK(doc != NULL);
    free(clean);
    free(text);
    return doc;
}

static const char *str(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsString(v) ? v->valuestring : "(missing)";
}

static void check_str(const cJSON *o, const char *key, const char *want)
{
    const char *got = str(o, key);
    if (strcmp(got, want))
        fprintf(stderr, "  \"%s\": '%s', want '%s'\n", key, got, want);
    CHECK(!strcmp(got, want));
}

/* The command line comes back as the cleaned argv. */
static void check_argv(const cJSON *o, int argc, char **argv)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(o, "command_line");
    CHECK_EQ_INT(cJSON_GetArraySize(a), argc);
    for (int i = 0; i < argc && i < cJSON_GetArraySize(a); i++) {
        char *want = rt_report_utf8(argv[i]);
        const cJSON *w = cJSON_GetArrayItem(a, i);
        const char *got = cJSON_IsString(w) ? w->valuestring : "(not a string)";
        if (strcmp(got, want))
            fprintf(stderr, "  argv[%d]: '%s', want '%s'\n", i, got, want);
        CHECK(!strcmp(got, want));
        free(want);
    }
}

int main(void)
{
    /* Valid UTF-8 stays; each bad byte becomes U+FFFD. */
    check_clean("plain ascii\t\n\"\\", "plain ascii\t\n\"\\");
    check_clean("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80", "caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80");
    check_clean("\xFF", FFFD);
    check_clean("a\x80z", "a" FFFD "z");                      /* stray continuation byte */
    check_clean("x\xC3", "x" FFFD);                            /* truncated at the end */
    check_clean("\xC3(", FFFD "(");                            /* truncated by an ASCII byte */
    check_clean("\xC0\xAF", FFFD FFFD);                        /* overlong '/' */
    check_clean("\xE0\x80\xAF", FFFD FFFD FFFD);               /* overlong, three bytes */
    check_clean("\xED\xA0\x80", FFFD FFFD FFFD);               /* a UTF-16 surrogate */
    check_clean("\xF4\x90\x80\x80", FFFD FFFD FFFD FFFD);      /* beyond U+10FFFF */
    check_clean("\xF4\x8F\xBF\xBF", "\xF4\x8F\xBF\xBF");       /* U+10FFFF itself */
    check_clean("\xEF\xBF\xBD", FFFD);                         /* U+FFFD itself */

    char dir[] = "/tmp/rt-report-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char stats[128], trace[128];
    snprintf(stats, sizeof stats, "%s/s.json", dir);
    snprintf(trace, sizeof trace, "%s/t.json", dir);

    char *argv[] = {"rt-mpi", "-o", "a\tb\nc\"d\\e\xFF\xC3.png", "--seed", "18446744073709551615", "\x01\x1F"};
    const int argc = (int)(sizeof argv / sizeof argv[0]);
    rt_job job = {0};
    job.width = 4, job.height = 2, job.samples = 3, job.max_depth = 5, job.seed = UINT64_MAX;
    rt_rank_stats ranks[2] = {{.units = 3, .rows = 1.5, .busy = 0.25}, {.units = 2, .rows = 0.5, .busy = 0.125}};
    rt_farm_result farm = {.msgs_in = 9, .bytes_in = (1ull << 53) + 1, .lost = 1};
    ranks[1].lost = 1, ranks[1].lost_at = 2.5, ranks[1].silent = 2.25, ranks[1].units_redone = 4, ranks[1].redone = 0.75;
    rt_run_summary s = {.job = &job,
                        .scene_hash = 0x0123456789abcdefull,
                        .image_hash = 42,
                        .output = argv[2],
                        .intersector = "bvh",
                        .ranks = 2,
                        .threads = 1,
                        .mpi = 1,
                        .units = 5,
                        .wall = 0.5,
                        .total_wall = 0.75,
                        .setup = 0.125,
                        .segments = (1ull << 60) + 1,
                        .per_rank = ranks,
                        .origin = {.argc = argc,
                                   .argv = argv,
                                   .start = 1700000000,
                                   .host = "node\xFF" "1",
                                   .mpi_library = "Test MPI 1.0",
                                   .slurm_job_id = "4242"},
                        .farm = &farm};
    CHECK_EQ_INT(rt_report_stats(stats, &s), 0);
    cJSON *doc = load(stats);
    if (doc) {
        check_str(doc, "output", "a\tb\nc\"d\\e" FFFD FFFD ".png");
        check_argv(doc, argc, argv);
        check_str(doc, "version", RT_VERSION);
        check_str(doc, "start_time", "2023-11-14T22:13:20Z");
        check_str(doc, "host", "node" FFFD "1");
        check_str(doc, "mpi_library", "Test MPI 1.0");
        check_str(doc, "slurm_job_id", "4242");
        check_str(doc, "scene_hash", "0123456789abcdef");
        check_str(doc, "image_hash", "000000000000002a");
        CHECK(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(doc, "mpi")));
        CHECK_NEAR(cJSON_GetObjectItemCaseSensitive(doc, "setup_seconds")->valuedouble, 0.125, 0);
        char features[96];
        rt_report_features(features, sizeof features, "Test MPI 1.0");
        const cJSON *f = cJSON_GetObjectItemCaseSensitive(doc, "features");
        char joined[96] = "";
        for (int i = 0; i < cJSON_GetArraySize(f); i++)
            snprintf(joined + strlen(joined), sizeof joined - strlen(joined), "%s%s", i ? " " : "",
                     cJSON_GetArrayItem(f, i)->valuestring);
        if (strcmp(joined, features))
            fprintf(stderr, "  features [%s], want [%s]\n", joined, features);
        CHECK(!strcmp(joined, features));
        const cJSON *pr = cJSON_GetObjectItemCaseSensitive(doc, "per_rank");
        CHECK_EQ_INT(cJSON_GetArraySize(pr), 2);
        CHECK_NEAR(cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(pr, 1), "busy_seconds")->valuedouble, 0.125, 0);
        CHECK_NEAR(cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(pr, 1), "idle_seconds")->valuedouble, 0.375, 0);
        /* what the lost rank cost; nothing of the kind for a rank not lost */
        CHECK_NEAR(cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(pr, 1), "lost_at_seconds")->valuedouble, 2.5, 0);
        CHECK_NEAR(cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(pr, 1), "silent_seconds")->valuedouble, 2.25, 0);
        CHECK_EQ_INT(cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(pr, 1), "units_redone")->valueint, 4);
        CHECK_NEAR(cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(pr, 1), "redone_seconds")->valuedouble, 0.75, 0);
        CHECK(cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(pr, 0), "lost_at_seconds") == NULL);
        cJSON_Delete(doc);
    }
    /* Whole numbers beyond 2^53 exactly as they are, not through a double. */
    char *text = slurp(stats);
    CHECK(text && strstr(text, "\"seed\":\t18446744073709551615,"));
    CHECK(text && strstr(text, "\"ray_segments\":\t1152921504606846977,"));
    /* the farm's figures: rank 0's bytes exact past 2^53, the lost rank */
    CHECK(text && strstr(text, "\"rank0_bytes_in\":\t9007199254740993,"));
    CHECK(text && strstr(text, "\"lost_ranks\":\t1,"));
    CHECK(text && strstr(text, "\"lost\":\ttrue"));
    free(text);

    /* Without Slurm, no job id at all. */
    s.origin.slurm_job_id = NULL;
    CHECK_EQ_INT(rt_report_stats(stats, &s), 0);
    if ((doc = load(stats))) {
        CHECK(cJSON_GetObjectItemCaseSensitive(doc, "slurm_job_id") == NULL);
        cJSON_Delete(doc);
    }

    /* The trace: one metadata event per rank, one event per unit, and the
     * same provenance in otherData. */
    rt_trace_event ev[2] = {{.rank = 1, .start = 0.5, .end = 0.75}, {.rank = 0, .start = 1e-6, .end = 2e-6}};
    ev[0].unit.id = 7, ev[0].unit.y0 = 2, ev[0].unit.y1 = 4, ev[0].unit.s0 = 0, ev[0].unit.s1 = 3;
    ev[0].unit.x0 = 16, ev[0].unit.x1 = 40;
    CHECK_EQ_INT(rt_report_trace(trace, ev, 2, 2, &s.origin), 0);
    if ((doc = load(trace))) {
        const cJSON *evs = cJSON_GetObjectItemCaseSensitive(doc, "traceEvents");
        CHECK_EQ_INT(cJSON_GetArraySize(evs), 4);
        const cJSON *u = cJSON_GetArrayItem(evs, 2);
        check_str(u, "name", "rows 2-4 x 16-40 s 0-3");
        check_str(u, "ph", "X");
        CHECK_NEAR(cJSON_GetObjectItemCaseSensitive(u, "ts")->valuedouble, 500000, 0);
        CHECK_NEAR(cJSON_GetObjectItemCaseSensitive(u, "dur")->valuedouble, 250000, 0);
        const cJSON *args = cJSON_GetObjectItemCaseSensitive(u, "args");
        CHECK_EQ_INT(cJSON_GetObjectItemCaseSensitive(args, "unit")->valueint, 7);
        CHECK_EQ_INT(cJSON_GetObjectItemCaseSensitive(args, "x0")->valueint, 16);
        CHECK_EQ_INT(cJSON_GetObjectItemCaseSensitive(args, "x1")->valueint, 40);
        const cJSON *other = cJSON_GetObjectItemCaseSensitive(doc, "otherData");
        check_argv(other, argc, argv);
        check_str(other, "version", RT_VERSION);
        cJSON_Delete(doc);
    }
    unlink(stats);
    unlink(trace);
    rmdir(dir);
    CHECK_DONE();
}
