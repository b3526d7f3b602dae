/* cli.h - command-line options: parsing, defaults and validation. Parsing
 * never prints; it fills an error message the caller reports. */
#ifndef RT_CLI_H
#define RT_CLI_H

#include <stddef.h>
#include <stdint.h>

#include "anim.h"
#include "frames.h"
#include "job.h"
#include "schedule.h"

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
    /* Russian roulette as asked: --roulette / --no-roulette; after parsing,
     * job.roulette holds the outcome (else on with the Sobol sampler and off
     * with the random one, whose images keep sampling version 2's bytes). */
    int roulette, no_roulette;
    int no_light_sampling; /* --no-light-sampling: job.light */
    const char *checkpoint; /* NULL until validated: default OUTPUT.ckpt */
    int no_checkpoint, resume, keep_checkpoint;
    uint32_t checkpoint_interval; /* seconds */
    const char *trace, *stats;  /* JSON outputs, or NULL */
    const char *done_file;      /* written once the image is, or NULL */
    uint32_t prefetch;
    uint32_t lease;          /* seconds of silence after which a rank is lost */
    double flush_interval;   /* seconds between a rank's sends of its sums; 0: only when asked */
    int split;               /* RT_SPLIT_COLUMNS or RT_SPLIT_SAMPLES (schedule.h) */
    uint32_t flush_mb;       /* a rank sends its sums once it holds this many MB */
    int empty_units;
    int serve_only;
    uint32_t passes;
    const char *preview; /* progressive preview file; NULL = the output */
    const char *spp_map; /* adaptive sampling: each pixel's samples as an image, or NULL */
    const char *scene;      /* named scene (scenes.h); "final" when no scene file is given */
    const char *scene_file; /* JSON scene file instead of a named scene */
    const char *dump_scene; /* write the scene as JSON here, then exit */
    const char *texture_dir; /* where named scenes find their images (earthmap.jpg); NULL: "." */
    uint64_t given;          /* bit i: option i of cli.c's table was on the command line */
    int bit_depth;          /* 8 or 16 (PNG, PPM) */
    int ppm_ascii;          /* PPM as P3 text */
    /* A frame job (issue 37): --frames A-B[:STEP] or --frame N given; then
     * --output, --spp-map, --stats and --trace are patterns (frames.h). */
    int frame_job;
    rt_frames frames;
    rt_anim_opts anim;      /* --turntable (and --shutter) */
    uint32_t frame;         /* a frame's copy of the options (rt_cli_frames_paths): its number */
} rt_options;

void rt_cli_defaults(rt_options *o);

/* Parses argv into o. A word that is no option is the scene file (as
 * --scene-file; every word after "--" is one). On RT_CLI_ERROR, err holds
 * one line (no prefix, no newline) naming the option and what is wrong,
 * with "did you mean --x?" for a mistyped long option, or the feature
 * this build lacks (JSON: scene files, --stats, --trace). Only checks that
 * need no file system access happen here. */
rt_cli_action rt_cli_parse(int argc, char **argv, rt_options *o, char *err, size_t errlen);

/* Checks the output path and the --preview path (directory exists and is
 * writable, not a directory, supported extension that this build writes,
 * --bit-depth/--ppm-ascii fit the format). */
int rt_cli_check_output(const rt_options *o, char *err, size_t errlen);

/* A file can be created at path (a file name in an existing, writable
 * directory): RT_OK, else the status (RT_EINVAL, RT_ENOENT, RT_EACCESS)
 * and a message naming opt. */
int rt_cli_check_path(const char *opt, const char *path, char *err, size_t errlen);

/* cli_frames.c: the frame job's options. */
/* --frames, --frame, --turntable, --shutter (lng without "--", name as given): RT_OK,
 * or RT_EINVAL with err filled. */
int rt_cli_frames_option(const char *lng, const char *name, const char *val, rt_options *o, char *err, size_t errlen);
/* Combinations that make no sense, once every option is read. */
int rt_cli_frames_settle(const rt_options *o, char *err, size_t errlen);
/* The per-frame files of a frame job: the patterns of --output, --spp-map,
 * --stats, --trace for one frame. */
#define RT_FRAME_PATTERNS 4
typedef struct rt_frame_paths {
    char path[RT_FRAME_PATTERNS][4096];
} rt_frame_paths;
/* fo = o for frame `frame`: its number and its files (in p, which must
 * outlive fo). RT_EINVAL or RT_EOVERFLOW as rt_frames_path. */
int rt_cli_frames_paths(const rt_options *o, uint32_t frame, rt_options *fo, rt_frame_paths *p);
/* Rank 0 before a frame job: the first frame's files can be created (as
 * rt_cli_check_output), no '#' in a directory, and no two files of the job
 * (patterns, checkpoint, done file) the same. */
int rt_cli_frames_check(const rt_options *o, char *err, size_t errlen);

/* Usage text for --help, grouped by topic; also the man page's source. */
const char *rt_cli_usage(void);
/* The i-th long option's name (without "--"), NULL past the last: the
 * tests check that the help names every one. */
const char *rt_cli_long_option(size_t i);

/* Parses a whole decimal number in [lo, hi]: RT_OK, RT_EINVAL (not a
 * number) or RT_ERANGE (outside [lo, hi]). */
int rt_cli_parse_u64(const char *s, uint64_t lo, uint64_t hi, uint64_t *out);

#endif
