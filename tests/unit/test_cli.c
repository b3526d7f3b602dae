/* test_cli.c - the option parser: defaults, every way of giving a value,
 * the positional scene file, each kind of bad input with its one-line
 * message (and "did you mean"), RT_ACCEL, the help's topics, and the
 * checks of output paths. Each case parses its own argv from defaults. */
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "accel.h"
#include "check.h"
#include "cli.h"
#include "exitcode.h"
#include "status.h"

static rt_options opt;
static char err[512];

/* Parses the NULL-terminated words after "rt-mpi" into opt. */
static rt_cli_action parse(const char *first, ...)
{
    char *argv[64] = {"rt-mpi"};
    int argc = 1;
    va_list ap;
    va_start(ap, first);
    for (const char *w = first; w && argc < 63; w = va_arg(ap, const char *))
        argv[argc++] = (char *)w;
    va_end(ap);
    rt_cli_defaults(&opt);
    err[0] = 0;
    return rt_cli_parse(argc, argv, &opt, err, sizeof err);
}

/* err contains want; prints both when not. */
static void check_err(const char *want)
{
    if (!strstr(err, want))
        fprintf(stderr, "  message '%s' lacks '%s'\n", err, want);
    CHECK(strstr(err, want) != NULL);
}

static void test_defaults(void)
{
    /* Defaults: the book's final scene at 1200 x 800, 500 spp. */
    CHECK_EQ_INT(parse(NULL), RT_CLI_RUN);
    CHECK_EQ_INT(opt.job.width, 1200);
    CHECK_EQ_INT(opt.job.height, 800);
    CHECK_EQ_INT(opt.job.samples, 500);
    CHECK_EQ_INT(opt.job.max_depth, 50);
    CHECK_EQ_U64(opt.job.seed, 42);
    CHECK(!strcmp(opt.scene, "final"));
    CHECK_EQ_INT(opt.accel, RT_ACCEL_BVH);
}

static void test_farm_knobs(void)
{
    /* The farm's knobs: how few rows are split, a flush interval in
     * fractions of a second (0: only when asked). */
    CHECK_EQ_INT(opt.split, RT_SPLIT_COLUMNS);
    CHECK_NEAR(opt.flush_interval, 0.1, 0);
    CHECK_EQ_INT(parse("--split", "samples", "--flush-interval", "0.25", NULL), RT_CLI_RUN);
    CHECK_EQ_INT(opt.split, RT_SPLIT_SAMPLES);
    CHECK_NEAR(opt.flush_interval, 0.25, 0);
    CHECK_EQ_INT(parse("--flush-interval=0", NULL), RT_CLI_RUN);
    CHECK_NEAR(opt.flush_interval, 0, 0);
    CHECK_EQ_INT(parse("--split", "rows", NULL), RT_CLI_ERROR);
    check_err("--split: 'rows' is not columns or samples");
    CHECK_EQ_INT(parse("--flush-interval", "-1", NULL), RT_CLI_ERROR);
    check_err("--flush-interval: '-1' is not a number of seconds");
}

static void test_value_forms(void)
{
    /* A value after the option, after '=', or attached to a short one. */
    CHECK_EQ_INT(parse("--width", "200", "-s", "8", "-j4", "--seed=7", NULL), RT_CLI_RUN);
    CHECK_EQ_INT(opt.job.width, 200);
    CHECK_EQ_INT(opt.job.height, 133); /* width / 1.5, truncated */
    CHECK_EQ_INT(opt.job.samples, 8);
    CHECK_EQ_INT(opt.threads, 4);
    CHECK_EQ_U64(opt.job.seed, 7);
    CHECK_EQ_INT(parse("--height", "10", "--max-depth", "3", "-o", "x.ppm", NULL), RT_CLI_RUN);
    CHECK_EQ_INT(opt.job.height, 10);
    CHECK_EQ_INT(opt.job.max_depth, 3);
    CHECK(!strcmp(opt.output, "x.ppm"));
}

static void test_bad_input(void)
{
    /* Bad input: one line naming the option and what is wrong. */
    CHECK_EQ_INT(parse("--wdith", "3", NULL), RT_CLI_ERROR);
    check_err("unknown option '--wdith'");
    CHECK_EQ_INT(parse("-s", NULL), RT_CLI_ERROR);
    check_err("option -s needs a value");
    CHECK_EQ_INT(parse("-s", "abc", NULL), RT_CLI_ERROR);
    check_err("-s: 'abc' is not a whole number");
    CHECK_EQ_INT(parse("--width", "0", NULL), RT_CLI_ERROR);
    check_err("--width: 0 is out of range");
    CHECK_EQ_INT(parse("--quiet=1", NULL), RT_CLI_ERROR);
    check_err("option --quiet takes no value");
    CHECK_EQ_INT(parse("--accel", "octree", NULL), RT_CLI_ERROR);
    check_err("--accel: 'octree' is not one of");
    CHECK_EQ_INT(parse("--scene", "nowhere", NULL), RT_CLI_ERROR);
    check_err("no scene named 'nowhere'");
    CHECK_EQ_INT(parse("--scene", "final", "--scene-file", "a.json", NULL), RT_CLI_ERROR);
    check_err("give one or the other");
    CHECK_EQ_INT(parse("--passes", "9", "-s", "4", NULL), RT_CLI_ERROR);
    check_err("9 passes need at least as many samples");
    CHECK_EQ_INT(parse("--no-checkpoint", "--resume", NULL), RT_CLI_ERROR);
    check_err("--no-checkpoint cannot be combined");
    CHECK_EQ_INT(parse("--width", "1", NULL), RT_CLI_ERROR);
    check_err("gives a height of 0");
}

static void test_mistyped(void)
{
    /* A mistyped long option: the nearest one (also for a unique start of
     * one), or only "see --help" when none is near. */
    CHECK_EQ_INT(parse("--wdith", "3", NULL), RT_CLI_ERROR);
    check_err("(did you mean --width?)");
    CHECK_EQ_INT(parse("--widht=3", NULL), RT_CLI_ERROR);
    check_err("unknown option '--widht' (did you mean --width?)");
    CHECK_EQ_INT(parse("--smaples", "3", NULL), RT_CLI_ERROR);
    check_err("(did you mean --samples?)");
    CHECK_EQ_INT(parse("--chekpoint-interval", "3", NULL), RT_CLI_ERROR);
    check_err("(did you mean --checkpoint-interval?)");
    CHECK_EQ_INT(parse("--no-checkpiont", NULL), RT_CLI_ERROR);
    check_err("(did you mean --no-checkpoint?)");
    CHECK_EQ_INT(parse("--sampels", "3", NULL), RT_CLI_ERROR);
    check_err("(did you mean --samples?)");
    CHECK_EQ_INT(parse("--bogus", NULL), RT_CLI_ERROR);
    check_err("unknown option '--bogus' (see --help)");
    CHECK_EQ_INT(parse("--s", "3", NULL), RT_CLI_ERROR); /* the start of several */
    check_err("unknown option '--s' (see --help)");
}

static void test_scene_word(void)
{
    /* The scene file as a word of its own, anywhere among the options. */
    CHECK_EQ_INT(parse("-s", "4", "scenes/example.json", "-o", "x.png", NULL), RT_CLI_RUN);
    CHECK(opt.scene_file && !strcmp(opt.scene_file, "scenes/example.json"));
    CHECK(opt.scene == NULL);
    CHECK_EQ_INT(opt.job.samples, 4);
    CHECK_EQ_INT(parse("--", "-odd.json", NULL), RT_CLI_RUN); /* after "--", no options */
    CHECK(opt.scene_file && !strcmp(opt.scene_file, "-odd.json"));
    CHECK_EQ_INT(parse("a.json", "b.json", NULL), RT_CLI_ERROR);
    check_err("unexpected argument 'b.json': one scene file only");
    CHECK_EQ_INT(parse("a.json", "--scene-file", "b.json", NULL), RT_CLI_ERROR);
    check_err("scene file 'a.json' and --scene-file b.json: give one or the other");
    CHECK_EQ_INT(parse("--scene", "final", "a.json", NULL), RT_CLI_ERROR);
    check_err("--scene and a scene file: give one or the other");
    CHECK_EQ_INT(parse("", NULL), RT_CLI_ERROR);
    check_err("scene file: empty file name");
}

static void test_help_wins(void)
{
    /* --help wins over a run and over other actions; not over bad input
     * met before it. */
    CHECK_EQ_INT(parse("--version", "--help", NULL), RT_CLI_HELP);
    CHECK_EQ_INT(parse("--list-scenes", NULL), RT_CLI_LIST_SCENES);
    CHECK_EQ_INT(parse("--dump-scene", "s.json", NULL), RT_CLI_DUMP_SCENE);
}

static void test_help_text(void)
{
    /* The help: every long option, grouped by topic in this order, the
     * developer knobs in a group of their own after the user's, then
     * examples, the environment and the exit status. */
    const char *help = rt_cli_usage();
    static const char *const topics[] = {"\nOutput:\n",      "\nScene:\n",       "\nSampling:\n",
                                         "\nParallel:\n",    "\nCheckpoint:\n",  "\nDiagnostics:\n",
                                         "\nDeveloper and benchmark options:\n", "\nExamples:\n",
                                         "\nEnvironment:\n", "\nExit status:\n"};
    const char *prev = help;
    for (size_t i = 0; i < sizeof topics / sizeof topics[0]; i++) {
        const char *at = strstr(help, topics[i]);
        if (!at || at < prev)
            fprintf(stderr, "  topic %s missing or out of order\n", topics[i] + 1);
        CHECK(at != NULL && at >= prev);
        prev = at ? at : prev;
    }
    const char *dev = strstr(help, "\nDeveloper and benchmark options:\n");
    const char *examples = strstr(help, "\nExamples:\n");
    size_t n_long = 0;
    for (const char *name; (name = rt_cli_long_option(n_long)); n_long++) {
        char item[64]; /* the option at the start of its item: "  --x" or ", --x" */
        snprintf(item, sizeof item, "--%s ", name);
        const char *at = NULL;
        for (const char *p = strstr(help, item); p && !at; p = strstr(p + 1, item))
            if (p[-1] == ' ' && (p[-2] == ' ' || p[-2] == ',') && p < examples)
                at = p;
        if (!at)
            snprintf(item, sizeof item, "--%s\n", name), at = strstr(help, item);
        int benchmark = !strcmp(name, "accel") || !strcmp(name, "prefetch") || !strcmp(name, "serve-only") ||
                        !strcmp(name, "empty-units");
        if (!at || (at > dev) != benchmark)
            fprintf(stderr, "  --%s: %s\n", name, !at ? "not in the help" : "in the wrong group");
        CHECK(at != NULL && (at > dev) == benchmark);
    }
    CHECK(n_long >= 30);
    static const char *const env[] = {"\n  OMP_NUM_THREADS ", "\n  RT_BIND ", "\n  RT_ACCEL ", "\n  RT_MPI_INIT ",
                                      "\n  OMPI_* "};
    const char *env_at = strstr(help, "\nEnvironment:\n");
    for (size_t i = 0; i < sizeof env / sizeof env[0]; i++) {
        const char *at = strstr(help, env[i]);
        if (!at || at < env_at)
            fprintf(stderr, "  environment variable%s not in the Environment section\n", env[i] + 2);
        CHECK(at != NULL && at > env_at);
    }
}

/* The help's line for one exit code at *at: its whole text, a line break
 * going on at the items' column (27). *at moves past it when it is there. */
static void check_exit_line(const char **at, int code, const char *text)
{
    char want[512];
    size_t len = (size_t)snprintf(want, sizeof want, "  %-25d", code);
    for (const char *t = text; *t && len + 30 < sizeof want; t++)
        len += *t == '\n' ? (size_t)snprintf(want + len, sizeof want - len, "\n%27s", "")
                           : (size_t)snprintf(want + len, sizeof want - len, "%c", *t);
    snprintf(want + len, sizeof want - len, "\n");
    int same = !strncmp(*at, want, strlen(want));
    if (!same)
        fprintf(stderr, "  exit status: want \"%s\"\n  got \"%.*s\"\n", want, (int)strlen(want), *at);
    CHECK(same);
    *at += same ? strlen(want) : strlen(*at);
}

static void test_help_exit_status(void)
{
    /* The help's last section is the exit-code table, every code in its
     * order; nothing after it, so nothing was cut. */
    const char *help = rt_cli_usage();
    const char *at = strstr(help, "\nExit status:\n");
    CHECK(at != NULL);
    at = at ? at + strlen("\nExit status:\n") : "";
#define RT_EXIT_CHECK(name, value, text) check_exit_line(&at, value, text);
    RT_EXIT_CODES(RT_EXIT_CHECK)
#undef RT_EXIT_CHECK
    CHECK_EQ_INT((int)strlen(at), 0);
}

static void test_accel_env(void)
{
    /* RT_ACCEL: a node's default among our BVH's variants; --accel wins. */
    setenv("RT_ACCEL", "bvh-scalar", 1);
    CHECK_EQ_INT(parse(NULL), RT_CLI_RUN);
    CHECK_EQ_INT(opt.accel, RT_ACCEL_BVH_SCALAR);
    CHECK_EQ_INT(parse("--accel", "bvh-sse", NULL), RT_CLI_RUN);
    CHECK_EQ_INT(opt.accel, RT_ACCEL_BVH_SSE);
    setenv("RT_ACCEL", "brute", 1); /* would still give the same image, but is no node setting */
    CHECK_EQ_INT(parse(NULL), RT_CLI_ERROR);
    check_err("RT_ACCEL='brute' is not one of bvh, bvh-sse, bvh-scalar");
    unsetenv("RT_ACCEL");
}

static void test_whole_numbers(void)
{
    /* Whole numbers: status codes, the full uint64 range. */
    uint64_t v = 0;
    CHECK_EQ_INT(rt_cli_parse_u64("18446744073709551615", 0, UINT64_MAX, &v), RT_OK);
    CHECK_EQ_U64(v, UINT64_MAX);
    CHECK_EQ_INT(rt_cli_parse_u64("18446744073709551616", 0, UINT64_MAX, &v), RT_ERANGE);
    CHECK_EQ_INT(rt_cli_parse_u64("5", 6, 9, &v), RT_ERANGE);
    CHECK_EQ_INT(rt_cli_parse_u64("", 0, 9, &v), RT_EINVAL);
    CHECK_EQ_INT(rt_cli_parse_u64("-1", 0, 9, &v), RT_EINVAL);
    CHECK_EQ_INT(rt_cli_parse_u64("1x", 0, 9, &v), RT_EINVAL);
}

static void test_output_paths(void)
{
    /* Output paths: a status and a message naming the option. */
    char dir[] = "/tmp/rt-cli-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256];
    CHECK_EQ_INT(rt_cli_check_path("--stats", dir, err, sizeof err), RT_EINVAL);
    check_err("is a directory");
    snprintf(path, sizeof path, "%s/missing/x.json", dir);
    CHECK_EQ_INT(rt_cli_check_path("--stats", path, err, sizeof err), RT_ENOENT);
    check_err("--stats: cannot write");
    snprintf(path, sizeof path, "%s/x.json", dir);
    CHECK_EQ_INT(rt_cli_check_path("--stats", path, err, sizeof err), RT_OK);
    snprintf(path, sizeof path, "%s/x.jpg", dir);
    CHECK_EQ_INT(parse("-o", path, NULL), RT_CLI_RUN);
    CHECK(rt_cli_check_output(&opt, err, sizeof err) != RT_OK);
    check_err("unsupported file type '.jpg'");
    snprintf(path, sizeof path, "%s/x.bmp", dir);
    CHECK_EQ_INT(parse("-o", path, "--bit-depth", "16", NULL), RT_CLI_RUN);
    CHECK(rt_cli_check_output(&opt, err, sizeof err) != RT_OK);
    check_err("--bit-depth 16");
    snprintf(path, sizeof path, "%s/x.png", dir);
    CHECK_EQ_INT(parse("-o", path, "--bit-depth", "16", NULL), RT_CLI_RUN);
    CHECK_EQ_INT(rt_cli_check_output(&opt, err, sizeof err), RT_OK);
    rmdir(dir);
}

int main(void)
{
    test_defaults();
    test_farm_knobs();
    test_value_forms();
    test_bad_input();
    test_mistyped();
    test_scene_word();
    test_help_wins();
    test_help_text();
    test_help_exit_status();
    test_accel_env();
    test_whole_numbers();
    test_output_paths();
    CHECK_DONE();
}
