/* cli.h - command-line options: parsing, defaults and validation. Parsing
 * never prints; it fills an error message the caller reports. */
#ifndef RT_CLI_H
#define RT_CLI_H

#include <stddef.h>
#include <stdint.h>

#include "job.h"

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
    rt_job job; /* job.height 0 = not given: width / 1.5 */
    int grid;
    int threads; /* 0 = all cores available to this rank */
    uint32_t band; /* rows per work unit; 0 = automatic */
    int quiet;
    int accel;   /* rt_accel_kind */
    const char *checkpoint; /* NULL until validated: default OUTPUT.ckpt */
    int no_checkpoint, resume, keep_checkpoint;
    uint32_t checkpoint_interval; /* seconds */
    const char *trace, *stats;  /* JSON outputs, or NULL */
    uint32_t prefetch;
    uint32_t lease;          /* seconds of silence after which a rank is lost */
    uint32_t flush_interval; /* seconds between a rank's sends of its sums; 0: only when asked */
    uint32_t flush_mb;       /* a rank sends its sums once it holds this many MB */
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
 * directory): RT_OK, else the status (RT_EINVAL, RT_ENOENT, RT_EACCESS)
 * and a message naming opt. */
int rt_cli_check_path(const char *opt, const char *path, char *err, size_t errlen);

/* Usage text for --help. */
const char *rt_cli_usage(void);

/* Parses a whole decimal number in [lo, hi]: RT_OK, RT_EINVAL (not a
 * number) or RT_ERANGE (outside [lo, hi]). */
int rt_cli_parse_u64(const char *s, uint64_t lo, uint64_t hi, uint64_t *out);

#endif
