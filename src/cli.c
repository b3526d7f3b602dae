/* cli.c - option table, strict number parsing and validation. */
#include "cli.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "accel.h"
#include "fileio.h"
#include "image_formats.h"
#include "material.h"
#include "render.h"
#include "scenes.h"
#include "status.h"

/* Largest width or height accepted; PNG's own limit is 2^31 - 1, but a
 * single rank must hold the accumulation buffer (24 bytes per pixel). */
#define MAX_DIM 1000000u
#define MAX_PIXELS (1ull << 32)

void rt_cli_defaults(rt_options *o)
{
    memset(o, 0, sizeof *o);
    o->output = "output.png";
    o->width = 1200;
    o->height = 0;
    o->samples = 500;
    o->grid = 11;
    o->max_depth = 50;
    o->threads = 0;
    o->seed = 42;
    o->band = 0;
    o->accel = RT_ACCEL_BVH;
    o->diffuse = RT_DIFFUSE_LAMBERTIAN;
    o->checkpoint_interval = 60;
    o->prefetch = 2;
    o->passes = 1;
    o->scene = "final";
    o->bit_depth = 8;
}

const char *rt_cli_usage(void)
{
    return "Usage: rt-mpi [OPTIONS]\n"
           "       mpirun -np N rt-mpi [OPTIONS]\n"
           "\n"
           "Renders the \"Ray Tracing in One Weekend\" scenes, distributing row bands\n"
           "over MPI ranks and OpenMP threads. The image is byte-identical for any number\n"
           "of ranks, threads and any band size.\n"
           "\n"
           "Options:\n"
           "  -o, --output <FILE>      Output image; the extension picks the format: .png, .ppm,\n"
           "                           .bmp, or .pfm/.exr (linear float) [default: output.png]\n"
           "      --bit-depth <BITS>   8 or 16 bits per channel (.png and .ppm) [default: 8]\n"
           "      --ppm-ascii          Write .ppm as ASCII P3, as the book does (default: binary P6)\n"
           "      --scene <NAME>       Scene to render (see --list-scenes) [default: final]\n"
           "      --scene-file <FILE>  Render the scene described by a JSON scene file instead\n"
           "      --dump-scene <FILE>  Write the scene this run would render as JSON, then exit\n"
           "      --list-scenes        List the named scenes and exit\n"
           "      --width <WIDTH>      Image width in pixels [default: 1200]\n"
           "      --height <HEIGHT>    Image height in pixels (default: width / 1.5)\n"
           "  -s, --samples <SAMPLES>  Samples per pixel [default: 500]\n"
           "      --grid <GRID>        Half-grid size N; 2N x 2N grid of small spheres [default: 11]\n"
           "      --max-depth <DEPTH>  Maximum ray segments per path [default: 50]\n"
           "  -j, --threads <THREADS>  Threads per rank (0 = all cores available to the rank) [default: 0]\n"
           "      --seed <SEED>        Scene and sampling seed [default: 42]\n"
           "      --band <ROWS>        Rows per work unit (0 = automatic) [default: 0]\n"
           "      --accel <NAME>       Intersector: bvh, brute (every sphere per ray) or embree\n"
           "                           (only in builds with -DRT_EMBREE=ON) [default: bvh]\n"
           "      --diffuse <MODEL>    lambertian, sphere or hemisphere [default: lambertian]\n"
           "      --checkpoint <FILE>  Checkpoint of finished rows [default: OUTPUT.ckpt]\n"
           "      --checkpoint-interval <SECONDS>  Time between checkpoint writes (0: whenever rows complete) [default: 60]\n"
           "      --resume             Continue from the checkpoint (refused if it is from another job)\n"
           "      --keep-checkpoint    Keep the checkpoint after a successful run\n"
           "      --no-checkpoint      Write no checkpoint\n"
           "      --trace <FILE.json>  Timeline of every work unit (Chrome trace format, Perfetto)\n"
           "      --stats <FILE.json>  Machine-readable run summary\n"
           "      --prefetch <N>       Work units a rank keeps in flight [default: 2]\n"
"      --passes <K>         Progressive: render the samples in K passes over the whole\n"
           "                           image, rewriting a preview after each [default: 1]\n"
           "      --preview <FILE>     Preview image of --passes [default: the output]\n"
           "      --serve-only         Rank 0 only hands out work (with several ranks)\n"
           "      --empty-units        Benchmark the farm: hand out and gather units without\n"
           "                           rendering them (the image is black)\n"
           "  -q, --quiet              No progress output on stderr\n"
           "      --version            Print version and exit\n"
           "  -h, --help               Print help\n"
           "\n"
           "Progress goes to stderr, the run summary (with the image hash) to stdout.\n"
           "Exit status: 0 done, 1 runtime failure, 2 bad input, 3 checkpoint refused,\n"
           "75 interrupted by SIGTERM/SIGINT/SIGUSR1 after saving the checkpoint (rerun with --resume).\n";
}

int rt_cli_parse_u64(const char *s, uint64_t lo, uint64_t hi, uint64_t *out)
{
    if (!s || !*s)
        return -1;
    uint64_t v = 0;
    for (const char *p = s; *p; p++) {
        if (*p < '0' || *p > '9')
            return -1;
        unsigned d = (unsigned)(*p - '0');
        if (v > (UINT64_MAX - d) / 10)
            return -2;
        v = v * 10 + d;
    }
    if (v < lo || v > hi)
        return -2;
    *out = v;
    return 0;
}

typedef struct optdef {
    const char *lng;
    char shrt;
    int has_arg;
    int id;
} optdef;

enum {
    O_OUTPUT,
    O_WIDTH,
    O_HEIGHT,
    O_SAMPLES,
    O_GRID,
    O_DEPTH,
    O_THREADS,
    O_SEED,
    O_BAND,
    O_ACCEL,
    O_DIFFUSE,
    O_QUIET,
    O_CHECKPOINT,
    O_NO_CHECKPOINT,
    O_RESUME,
    O_KEEP_CHECKPOINT,
    O_CKPT_INTERVAL,
    O_TRACE,
    O_STATS,
    O_PREFETCH,
    O_EMPTY_UNITS,
    O_SERVE_ONLY,
    O_PASSES,
    O_PREVIEW,
    O_VERSION,
    O_HELP,
    O_SCENE,
    O_SCENE_FILE,
    O_DUMP_SCENE,
    O_LIST_SCENES,
    O_BIT_DEPTH,
    O_PPM_ASCII
};

static const optdef OPTS[] = {
    {"output", 'o', 1, O_OUTPUT},   {"width", 0, 1, O_WIDTH},       {"height", 0, 1, O_HEIGHT},
    {"samples", 's', 1, O_SAMPLES}, {"grid", 0, 1, O_GRID},         {"max-depth", 0, 1, O_DEPTH},
    {"threads", 'j', 1, O_THREADS}, {"seed", 0, 1, O_SEED},         {"band", 0, 1, O_BAND},
    {"accel", 0, 1, O_ACCEL},       {"diffuse", 0, 1, O_DIFFUSE},   {"quiet", 'q', 0, O_QUIET},
    {"version", 0, 0, O_VERSION},   {"help", 'h', 0, O_HELP},       {"checkpoint", 0, 1, O_CHECKPOINT},
    {"no-checkpoint", 0, 0, O_NO_CHECKPOINT}, {"resume", 0, 0, O_RESUME}, {"keep-checkpoint", 0, 0, O_KEEP_CHECKPOINT},
    {"checkpoint-interval", 0, 1, O_CKPT_INTERVAL}, {"trace", 0, 1, O_TRACE}, {"stats", 0, 1, O_STATS},
    {"prefetch", 0, 1, O_PREFETCH}, {"empty-units", 0, 0, O_EMPTY_UNITS},
    {"serve-only", 0, 0, O_SERVE_ONLY}, {"passes", 0, 1, O_PASSES}, {"preview", 0, 1, O_PREVIEW},
    {"scene", 0, 1, O_SCENE},       {"scene-file", 0, 1, O_SCENE_FILE}, {"dump-scene", 0, 1, O_DUMP_SCENE}, {"list-scenes", 0, 0, O_LIST_SCENES},
    {"bit-depth", 0, 1, O_BIT_DEPTH},   {"ppm-ascii", 0, 0, O_PPM_ASCII},
};
#define N_OPTS (sizeof OPTS / sizeof OPTS[0])

static int number(const char *name, const char *val, uint64_t lo, uint64_t hi, uint64_t *out, char *err,
                  size_t errlen)
{
    int r = rt_cli_parse_u64(val, lo, hi, out);
    if (r == -1)
        snprintf(err, errlen, "%s: '%s' is not a whole number", name, val);
    else if (r == -2)
        snprintf(err, errlen, "%s: %s is out of range (%llu to %llu)", name, val, (unsigned long long)lo,
                 (unsigned long long)hi);
    return r;
}

rt_cli_action rt_cli_parse(int argc, char **argv, rt_options *o, char *err, size_t errlen)
{
    rt_cli_action action = RT_CLI_RUN;
    int scene_given = 0;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const optdef *d = NULL;
        const char *val = NULL;
        char name[64];
        if (arg[0] == '-' && arg[1] == '-' && arg[2]) {
            const char *eq = strchr(arg + 2, '=');
            size_t len = eq ? (size_t)(eq - arg - 2) : strlen(arg + 2);
            for (size_t k = 0; k < N_OPTS; k++)
                if (strlen(OPTS[k].lng) == len && !strncmp(OPTS[k].lng, arg + 2, len))
                    d = &OPTS[k];
            if (!d) {
                snprintf(err, errlen, "unknown option '%.*s' (see --help)", (int)(eq ? (size_t)(eq - arg) : strlen(arg)),
                         arg);
                return RT_CLI_ERROR;
            }
            if (eq) {
                if (!d->has_arg) {
                    snprintf(err, errlen, "option --%s takes no value", d->lng);
                    return RT_CLI_ERROR;
                }
                val = eq + 1;
            }
            snprintf(name, sizeof name, "--%s", d->lng);
        } else if (arg[0] == '-' && arg[1] && arg[1] != '-') {
            for (size_t k = 0; k < N_OPTS; k++)
                if (OPTS[k].shrt == arg[1])
                    d = &OPTS[k];
            if (!d) {
                snprintf(err, errlen, "unknown option '%s' (see --help)", arg);
                return RT_CLI_ERROR;
            }
            if (arg[2]) {
                if (!d->has_arg) {
                    snprintf(err, errlen, "unknown option '%s' (see --help)", arg);
                    return RT_CLI_ERROR;
                }
                val = arg + 2; /* -j4 */
            }
            snprintf(name, sizeof name, "-%c", d->shrt);
        } else {
            snprintf(err, errlen, "unexpected argument '%s' (see --help)", arg);
            return RT_CLI_ERROR;
        }
        if (d->has_arg && !val) {
            if (i + 1 >= argc) {
                snprintf(err, errlen, "option %s needs a value", name);
                return RT_CLI_ERROR;
            }
            val = argv[++i];
        }
        uint64_t v = 0;
        switch (d->id) {
        case O_OUTPUT:
            if (!*val) {
                snprintf(err, errlen, "%s: empty file name", name);
                return RT_CLI_ERROR;
            }
            o->output = val;
            break;
        case O_WIDTH:
            if (number(name, val, 1, MAX_DIM, &v, err, errlen))
                return RT_CLI_ERROR;
            o->width = (uint32_t)v;
            break;
        case O_HEIGHT:
            if (number(name, val, 1, MAX_DIM, &v, err, errlen))
                return RT_CLI_ERROR;
            o->height = (uint32_t)v;
            o->height_given = 1;
            break;
        case O_SAMPLES:
            if (number(name, val, 1, RT_MAX_SAMPLES, &v, err, errlen))
                return RT_CLI_ERROR;
            o->samples = (uint32_t)v;
            break;
        case O_GRID:
            if (number(name, val, 0, 1000, &v, err, errlen))
                return RT_CLI_ERROR;
            o->grid = (int)v;
            break;
        case O_DEPTH:
            if (number(name, val, 1, 100000, &v, err, errlen))
                return RT_CLI_ERROR;
            o->max_depth = (uint32_t)v;
            break;
        case O_THREADS:
            if (number(name, val, 0, 4096, &v, err, errlen))
                return RT_CLI_ERROR;
            o->threads = (int)v;
            break;
        case O_SEED:
            if (number(name, val, 0, UINT64_MAX, &v, err, errlen))
                return RT_CLI_ERROR;
            o->seed = v;
            break;
        case O_BAND:
            if (number(name, val, 0, MAX_DIM, &v, err, errlen))
                return RT_CLI_ERROR;
            o->band = (uint32_t)v;
            break;
        case O_ACCEL: {
            int k = rt_accel_parse(val);
            if (k < 0) {
                snprintf(err, errlen, "%s: '%s' is not one of bvh, brute, embree", name, val);
                return RT_CLI_ERROR;
            }
            o->accel = k;
            break;
        }
        case O_DIFFUSE:
            if (!strcmp(val, "lambertian"))
                o->diffuse = RT_DIFFUSE_LAMBERTIAN;
            else if (!strcmp(val, "sphere"))
                o->diffuse = RT_DIFFUSE_SPHERE;
            else if (!strcmp(val, "hemisphere"))
                o->diffuse = RT_DIFFUSE_HEMISPHERE;
            else {
                snprintf(err, errlen, "%s: '%s' is not one of lambertian, sphere, hemisphere", name, val);
                return RT_CLI_ERROR;
            }
            break;
        case O_QUIET:
            o->quiet = 1;
            break;
        case O_CHECKPOINT:
        case O_TRACE:
        case O_STATS:
            if (!*val) {
                snprintf(err, errlen, "%s: empty file name", name);
                return RT_CLI_ERROR;
            }
            if (d->id == O_CHECKPOINT)
                o->checkpoint = val;
            else if (d->id == O_TRACE)
                o->trace = val;
            else
                o->stats = val;
            break;
        case O_NO_CHECKPOINT:
            o->no_checkpoint = 1;
            break;
        case O_RESUME:
            o->resume = 1;
            break;
        case O_KEEP_CHECKPOINT:
            o->keep_checkpoint = 1;
            break;
        case O_CKPT_INTERVAL:
            if (number(name, val, 0, 86400, &v, err, errlen))
                return RT_CLI_ERROR;
            o->checkpoint_interval = (uint32_t)v;
            break;
        case O_PASSES:
            if (number(name, val, 1, RT_MAX_SAMPLES, &v, err, errlen))
                return RT_CLI_ERROR;
            o->passes = (uint32_t)v;
            break;
        case O_PREVIEW:
            if (!*val) {
                snprintf(err, errlen, "%s: empty file name", name);
                return RT_CLI_ERROR;
            }
            o->preview = val;
            break;
        case O_SERVE_ONLY:
            o->serve_only = 1;
            break;
        case O_EMPTY_UNITS:
            o->empty_units = 1;
            break;
        case O_PREFETCH:
            if (number(name, val, 1, 64, &v, err, errlen))
                return RT_CLI_ERROR;
            o->prefetch = (uint32_t)v;
            break;
        case O_VERSION:
            if (action == RT_CLI_RUN)
                action = RT_CLI_VERSION;
            break;
        case O_HELP:
            action = RT_CLI_HELP;
            break;
        case O_SCENE: {
            int known = 0;
            for (unsigned k = 0; k < rt_scenes_count(); k++)
                known |= !strcmp(val, rt_scenes_info(k)->name);
            if (!known) {
                snprintf(err, errlen, "%s: no scene named '%s' (see --list-scenes)", name, val);
                return RT_CLI_ERROR;
            }
            o->scene = val;
            scene_given = 1;
            break;
        }
        case O_SCENE_FILE:
        case O_DUMP_SCENE:
            if (!*val) {
                snprintf(err, errlen, "%s: empty file name", name);
                return RT_CLI_ERROR;
            }
            *(d->id == O_SCENE_FILE ? &o->scene_file : &o->dump_scene) = val;
            break;
        case O_LIST_SCENES:
            if (action == RT_CLI_RUN)
                action = RT_CLI_LIST_SCENES;
            break;
        case O_BIT_DEPTH:
            if (strcmp(val, "8") && strcmp(val, "16")) {
                snprintf(err, errlen, "%s: '%s' is not 8 or 16", name, val);
                return RT_CLI_ERROR;
            }
            o->bit_depth = val[0] == '8' ? 8 : 16;
            break;
        case O_PPM_ASCII:
            o->ppm_ascii = 1;
            break;
        }
    }
    if (action != RT_CLI_RUN)
        return action;
    if (scene_given && o->scene_file) {
        snprintf(err, errlen, "--scene and --scene-file: give one or the other");
        return RT_CLI_ERROR;
    }
    if (!o->height_given) {
        o->height = (uint32_t)((double)o->width / 1.5);
        if (o->height == 0) {
            snprintf(err, errlen, "--width: %u gives a height of 0 (width / 1.5); give --height", o->width);
            return RT_CLI_ERROR;
        }
    }
    if (o->no_checkpoint && (o->resume || o->checkpoint)) {
        snprintf(err, errlen, "--no-checkpoint cannot be combined with --resume or --checkpoint");
        return RT_CLI_ERROR;
    }
    if (o->passes > o->samples) {
        snprintf(err, errlen, "--passes: %u passes need at least as many samples (-s %u)", o->passes, o->samples);
        return RT_CLI_ERROR;
    }
    if ((uint64_t)o->width * o->height > MAX_PIXELS) {
        snprintf(err, errlen, "image of %u x %u pixels is too large (at most %llu pixels)", o->width, o->height,
                 (unsigned long long)MAX_PIXELS);
        return RT_CLI_ERROR;
    }
    return RT_CLI_RUN;
}

/* The file can be created: a file name, in a writable directory. */
static int check_path(const char *opt, const char *path, char *err, size_t errlen)
{
    const char *slash = strrchr(path, '/');
    if (!*(slash ? slash + 1 : path)) {
        snprintf(err, errlen, "%s: '%s' names a directory, not a file", opt, path);
        return -1;
    }
    int st = rt_file_check_writable(path);
    if (st == RT_EINVAL) {
        snprintf(err, errlen, "%s: '%s' is a directory", opt, path);
        return -1;
    }
    if (st) {
        snprintf(err, errlen, "%s: cannot write '%s': directory does not exist or is not writable", opt, path);
        return -1;
    }
    return 0;
}

/* An image path: supported extension, options that fit its format, and a
 * file that can be created. */
static int check_image_path(const char *opt, const char *path, const rt_options *o, char *err, size_t errlen)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    rt_image_format fmt = rt_image_format_from_path(path);
    rt_image_write_opts wo = {o->bit_depth, o->ppm_ascii, NULL, 0};
    if (*base && fmt == RT_FORMAT_UNKNOWN) {
        snprintf(err, errlen, "%s: unsupported file type '%s' (supported: %s)", opt, dot ? dot : base,
                 rt_image_format_list());
        return -1;
    }
    if (*base && rt_image_check_opts(fmt, &wo) != RT_OK) {
        if (o->ppm_ascii && fmt != RT_FORMAT_PPM)
            snprintf(err, errlen, "--ppm-ascii: %s '%s' is not a .ppm file", opt, path);
        else
            snprintf(err, errlen, "--bit-depth %d: %s files are written %s", o->bit_depth, dot,
                     fmt == RT_FORMAT_BMP ? "with 8 bits per channel only" : "as 32-bit float");
        return -1;
    }
    return check_path(opt, path, err, errlen);
}

int rt_cli_check_output(const rt_options *o, char *err, size_t errlen)
{
    if (o->dump_scene) /* the run ends after the dump: no image is written */
        return check_path("--dump-scene", o->dump_scene, err, errlen);
    if (check_image_path("--output", o->output, o, err, errlen))
        return -1;
    return o->preview ? check_image_path("--preview", o->preview, o, err, errlen) : 0;
}
