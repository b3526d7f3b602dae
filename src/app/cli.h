/* cli.h - command-line options: parsing, defaults and validation. Parsing
 * never prints; it fills an error message the caller reports. */
#ifndef RT_CLI_H
#define RT_CLI_H

#include <stddef.h>
#include <stdint.h>

#define RT_VERSION "0.1.0"

typedef enum rt_cli_action {
    RT_CLI_RUN = 0,
    RT_CLI_HELP = 1,
    RT_CLI_VERSION = 2,
    RT_CLI_ERROR = 3,
    RT_CLI_LIST_SCENES = 4,
    RT_CLI_DUMP_SCENE = 5, /* write the scene as JSON and end */
} rt_cli_action;

typedef struct rt_options {
    const char *output;
    uint32_t width, height; /* height 0 = not given: width / 1.5 */
    uint32_t samples;
    int grid;
    uint32_t max_depth;
    int threads; /* 0 = all cores available to this rank */
    uint64_t seed;
    uint32_t band; /* rows per work unit; 0 = automatic */
    int quiet;
    int accel;   /* rt_accel_kind */
    int diffuse; /* rt_diffuse */
    int sampler; /* rt_sampler_kind */
    /* Russian roulette: after parsing 1 or 0; --roulette / --no-roulette,
     * else on with the Sobol sampler and off with the random one (whose
     * images keep sampling version 2's bytes). */
    int roulette, no_roulette;
    const char *checkpoint; /* NULL until validated: default OUTPUT.ckpt */
    int no_checkpoint, resume, keep_checkpoint;
    uint32_t checkpoint_interval; /* seconds */
    const char *trace, *stats;  /* JSON outputs, or NULL */
    uint32_t prefetch;
    int empty_units;
    int serve_only;
    uint32_t passes;
    const char *preview; /* progressive preview file; NULL = the output */
    const char *scene;      /* named scene (scenes.h); "final" when no scene file is given */
    const char *scene_file; /* JSON scene file instead of a named scene */
    const char *dump_scene; /* write the scene as JSON here, then exit */
    int bit_depth;          /* 8 or 16 (PNG, PPM) */
    int ppm_ascii;          /* PPM as P3 text */
} rt_options;

void rt_cli_defaults(rt_options *o);

/* Parses argv into o. On RT_CLI_ERROR, err holds one line (no prefix, no
 * newline) naming the option and what is wrong. Only checks that need no
 * file system access happen here. */
rt_cli_action rt_cli_parse(int argc, char **argv, rt_options *o, char *err, size_t errlen);

/* Checks the output path and the --preview path (directory exists and is
 * writable, not a directory, supported extension, --bit-depth/--ppm-ascii
 * fit the format). */
int rt_cli_check_output(const rt_options *o, char *err, size_t errlen);

/* A file can be created at path (a file name in an existing, writable
 * directory); else -1 and a message naming opt. */
int rt_cli_check_path(const char *opt, const char *path, char *err, size_t errlen);

/* Usage text for --help. */
const char *rt_cli_usage(void);

/* Parses a whole decimal number in [lo, hi]; 0 on success. */
int rt_cli_parse_u64(const char *s, uint64_t lo, uint64_t hi, uint64_t *out);

#endif
