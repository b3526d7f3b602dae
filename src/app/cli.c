/* cli.c - option table, strict number parsing and validation. */
#include "cli.h"

#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "accel.h"
#include "material.h"
#include "policy.h"
#include "render.h" /* RT_MAX_SAMPLES */
#include "rt_config.h"
#include "sampler.h"
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
    o->job.width = 1200;
    o->job.height = 0;
    o->job.samples = 500;
    o->grid = 11;
    o->job.max_depth = 50;
    o->threads = 0;
    o->job.seed = 42;
    o->band = 0;
    o->accel = RT_ACCEL_BVH;
    o->job.diffuse = RT_DIFFUSE_LAMBERTIAN;
    o->job.sampler = RT_SAMPLER_SOBOL;
    o->checkpoint_interval = 60;
    o->prefetch = RT_POLICY_PREFETCH;
    o->lease = RT_POLICY_LEASE;
    o->flush_interval = RT_POLICY_FLUSH_INTERVAL;
    o->flush_mb = RT_POLICY_FLUSH_MB;
    o->passes = 1;
    o->bit_depth = 8;
}

/* How an option's value is stored: most options are a number in a range or
 * a file name written straight into an rt_options field (by offset); only
 * the few that name a choice or change the action need code of their own. */
typedef enum optkind {
    K_FLAG,   /* int field set to 1 */
    K_U32,    /* uint32_t field, whole number in [lo, hi] */
    K_INT,    /* int field, whole number in [lo, hi] */
    K_U64,    /* uint64_t field, whole number in [lo, hi] */
    K_PATH,   /* const char * field, non-empty */
    K_SPECIAL, /* names, real numbers, lists: parsed one by one in special() */
    K_ACTION, /* help, version, list-scenes */
} optkind;

typedef struct optdef {
    const char *lng;
    char shrt;
    optkind kind;
    size_t off; /* field in rt_options (K_FLAG .. K_PATH) */
    uint64_t lo, hi;
} optdef;

#define F(field) offsetof(rt_options, field)
static const optdef OPTS[] = {
    {"output", 'o', K_PATH, F(output), 0, 0},
    {"width", 0, K_U32, F(job.width), 1, MAX_DIM},
    {"height", 0, K_U32, F(job.height), 1, MAX_DIM},
    {"samples", 's', K_U32, F(job.samples), 1, RT_MAX_SAMPLES},
    {"grid", 0, K_INT, F(grid), 0, 1000},
    {"max-depth", 0, K_U32, F(job.max_depth), 1, 100000},
    {"threads", 'j', K_INT, F(threads), 0, 4096},
    {"seed", 0, K_U64, F(job.seed), 0, UINT64_MAX},
    {"band", 0, K_U32, F(band), 0, MAX_DIM},
    {"accel", 0, K_SPECIAL, 0, 0, 0},
    {"diffuse", 0, K_SPECIAL, 0, 0, 0},
    {"sampler", 0, K_SPECIAL, 0, 0, 0},
    {"roulette", 0, K_FLAG, F(roulette), 0, 0},
    {"no-roulette", 0, K_FLAG, F(no_roulette), 0, 0},
    {"no-light-sampling", 0, K_FLAG, F(no_light_sampling), 0, 0},
    {"scene", 0, K_SPECIAL, 0, 0, 0},
    {"bit-depth", 0, K_SPECIAL, 0, 0, 0},
    {"scene-file", 0, K_PATH, F(scene_file), 0, 0},
    {"dump-scene", 0, K_PATH, F(dump_scene), 0, 0},
    {"texture-dir", 0, K_PATH, F(texture_dir), 0, 0},
    {"ppm-ascii", 0, K_FLAG, F(ppm_ascii), 0, 0},
    {"quiet", 'q', K_FLAG, F(quiet), 0, 0},
    {"checkpoint", 0, K_PATH, F(checkpoint), 0, 0},
    {"no-checkpoint", 0, K_FLAG, F(no_checkpoint), 0, 0},
    {"resume", 0, K_FLAG, F(resume), 0, 0},
    {"keep-checkpoint", 0, K_FLAG, F(keep_checkpoint), 0, 0},
    {"checkpoint-interval", 0, K_U32, F(checkpoint_interval), 0, 86400},
    {"trace", 0, K_PATH, F(trace), 0, 0},
    {"stats", 0, K_PATH, F(stats), 0, 0},
    {"done-file", 0, K_PATH, F(done_file), 0, 0},
    {"prefetch", 0, K_U32, F(prefetch), 1, 64},
    {"lease", 0, K_U32, F(lease), 1, 86400},
    {"flush-interval", 0, K_SPECIAL, 0, 0, 0},
    {"split", 0, K_SPECIAL, 0, 0, 0},
    {"flush-mb", 0, K_U32, F(flush_mb), 1, 1u << 20},
    {"passes", 0, K_U32, F(passes), 1, RT_MAX_SAMPLES},
    {"preview", 0, K_PATH, F(preview), 0, 0},
    {"noise-threshold", 0, K_SPECIAL, 0, 0, 0},
    {"spp-map", 0, K_PATH, F(spp_map), 0, 0},
    {"aov", 0, K_SPECIAL, 0, 0, 0},
    {"shutter", 0, K_SPECIAL, 0, 0, 0},
    {"frames", 0, K_SPECIAL, 0, 0, 0},
    {"frame", 0, K_SPECIAL, 0, 0, 0},
    {"turntable", 0, K_SPECIAL, 0, 0, 0},
    {"serve-only", 0, K_FLAG, F(serve_only), 0, 0},
    {"empty-units", 0, K_FLAG, F(empty_units), 0, 0},
    {"list-scenes", 0, K_ACTION, RT_CLI_LIST_SCENES, 0, 0},
    {"version", 0, K_ACTION, RT_CLI_VERSION, 0, 0},
    {"help", 'h', K_ACTION, RT_CLI_HELP, 0, 0},
};
#undef F
#define N_OPTS (sizeof OPTS / sizeof OPTS[0])
_Static_assert(N_OPTS <= 64, "rt_options.given has a bit per option");

const char *rt_cli_long_option(size_t i) { return i < N_OPTS ? OPTS[i].lng : NULL; }

static int number(const char *name, const char *val, uint64_t lo, uint64_t hi, uint64_t *out, char *err,
                  size_t errlen)
{
    int r = rt_cli_parse_u64(val, lo, hi, out);
    if (r == RT_EINVAL)
        snprintf(err, errlen, "%s: '%s' is not a whole number", name, val);
    else if (r == RT_ERANGE)
        snprintf(err, errlen, "%s: %s is out of range (%llu to %llu)", name, val, (unsigned long long)lo,
                 (unsigned long long)hi);
    return r;
}

/* A real number in (lo, hi] (above_lo) or [lo, hi]: RT_OK or RT_EINVAL. */
static int real(const char *val, double lo, double hi, int above_lo, double *out)
{
    char *end;
    double v = strtod(val, &end);
    if (end == val || *end || !(above_lo ? v > lo : v >= lo) || !(v <= hi))
        return RT_EINVAL;
    *out = v;
    return RT_OK;
}

/* The options whose value needs code of its own: a name from a set of
 * choices, a real number, a list. */
static int special(const optdef *d, const char *name, const char *val, rt_options *o, char *err, size_t errlen)
{
    int k;
    if (!strcmp(d->lng, "frames") || !strcmp(d->lng, "frame") || !strcmp(d->lng, "turntable") ||
        !strcmp(d->lng, "shutter"))
        return rt_cli_frames_option(d->lng, name, val, o, err, errlen);
    if (!strcmp(d->lng, "accel")) {
        if ((k = rt_accel_parse(val)) < 0) {
            snprintf(err, errlen, "%s: '%s' is not one of bvh, brute, embree, bvh-scalar, bvh-sse", name, val);
            return RT_EINVAL;
        }
        o->accel = k;
    } else if (!strcmp(d->lng, "diffuse")) {
        if ((k = rt_diffuse_parse(val)) < 0) {
            snprintf(err, errlen, "%s: '%s' is not one of lambertian, sphere, hemisphere", name, val);
            return RT_EINVAL;
        }
        o->job.diffuse = (rt_diffuse)k;
    } else if (!strcmp(d->lng, "sampler")) {
        if ((k = rt_sampler_parse(val)) < 0) {
            snprintf(err, errlen, "%s: '%s' is not one of sobol, random", name, val);
            return RT_EINVAL;
        }
        o->job.sampler = (rt_sampler_kind)k;
    } else if (!strcmp(d->lng, "bit-depth")) {
        if (strcmp(val, "8") && strcmp(val, "16")) {
            snprintf(err, errlen, "%s: '%s' is not 8 or 16", name, val);
            return RT_EINVAL;
        }
        o->bit_depth = val[0] == '8' ? 8 : 16;
    } else if (!strcmp(d->lng, "noise-threshold")) {
        if (real(val, 0.0, 1.0, 1, &o->job.noise_threshold)) {
            snprintf(err, errlen, "%s: '%s' is not a number above 0 and at most 1", name, val);
            return RT_EINVAL;
        }
    } else if (!strcmp(d->lng, "flush-interval")) {
        if (real(val, 0.0, 86400.0, 0, &o->flush_interval)) {
            snprintf(err, errlen, "%s: '%s' is not a number of seconds from 0 to 86400", name, val);
            return RT_EINVAL;
        }
    } else if (!strcmp(d->lng, "split")) {
        if (strcmp(val, "columns") && strcmp(val, "samples")) {
            snprintf(err, errlen, "%s: '%s' is not columns or samples", name, val);
            return RT_EINVAL;
        }
        o->split = val[0] == 'c' ? RT_SPLIT_COLUMNS : RT_SPLIT_SAMPLES;
    } else if (!strcmp(d->lng, "aov")) {
        o->job.aov = 0;
        for (const char *p = val; *p;) {
            size_t n = strcspn(p, ",");
            if (n == 6 && !strncmp(p, "albedo", 6)) {
                o->job.aov |= RT_AOV_ALBEDO;
            } else if (n == 6 && !strncmp(p, "normal", 6)) {
                o->job.aov |= RT_AOV_NORMAL;
            } else {
                snprintf(err, errlen, "%s: '%.*s' is not albedo or normal", name, (int)n, p);
                return RT_EINVAL;
            }
            p += n + (p[n] == ',');
        }
        if (!o->job.aov) {
            snprintf(err, errlen, "%s: name albedo, normal or both (albedo,normal)", name);
            return RT_EINVAL;
        }
    } else { /* scene */
        int known = 0;
        for (unsigned i = 0; i < rt_scenes_count(); i++)
            known |= !strcmp(val, rt_scenes_info(i)->name);
        if (!known) {
            snprintf(err, errlen, "%s: no scene named '%s' (see --list-scenes)", name, val);
            return RT_EINVAL;
        }
        o->scene = val;
    }
    return RT_OK;
}

/* Stores val (NULL for options without one) as d says. */
static int apply(const optdef *d, const char *name, const char *val, rt_options *o, rt_cli_action *action,
                 char *err, size_t errlen)
{
    char *field = (char *)o + d->off;
    uint64_t v = 0;
    switch (d->kind) {
    case K_FLAG:
        *(int *)field = 1;
        return RT_OK;
    case K_U32:
    case K_INT:
    case K_U64:
        if (number(name, val, d->lo, d->hi, &v, err, errlen))
            return RT_EINVAL;
        if (d->kind == K_U32)
            *(uint32_t *)field = (uint32_t)v;
        else if (d->kind == K_INT)
            *(int *)field = (int)v;
        else
            *(uint64_t *)field = v;
        return RT_OK;
    case K_PATH:
        if (!*val) {
            snprintf(err, errlen, "%s: empty file name", name);
            return RT_EINVAL;
        }
        *(const char **)field = val;
        return RT_OK;
    case K_SPECIAL:
        return special(d, name, val, o, err, errlen);
    case K_ACTION:
        /* --help wins over the others, --list-scenes and --version over a run */
        if (*action == RT_CLI_RUN || d->off == RT_CLI_HELP)
            *action = (rt_cli_action)d->off;
        return RT_OK;
    }
    return RT_OK;
}

/* RT_ACCEL: a node's own default for --accel, set by a site per node (say,
 * bvh-scalar on nodes without SSE2, bvh-sse to match a mixed cluster).
 * Only our BVH's variants, which find the very same hits: ranks of one job
 * may differ in it and still make the same image. --accel wins over it. */
static int accel_from_env(rt_options *o, char *err, size_t errlen)
{
    const char *env = getenv("RT_ACCEL");
    if (!env || !*env)
        return RT_OK;
    int k = rt_accel_parse(env);
    if (k != RT_ACCEL_BVH && k != RT_ACCEL_BVH_SSE && k != RT_ACCEL_BVH_SCALAR) {
        snprintf(err, errlen, "RT_ACCEL='%s' is not one of bvh, bvh-sse, bvh-scalar", env);
        return RT_EINVAL;
    }
    o->accel = k;
    return RT_OK;
}

/* Edits (insert, delete, replace, swap two neighbours) from a to b, the
 * first n bytes of a against b; stops counting past 9. */
static int edit_distance(const char *a, size_t n, const char *b)
{
    size_t m = strlen(b);
    if (n > 40 || m > 40)
        return 9;
    int d[41][41];
    for (size_t i = 0; i <= n; i++)
        for (size_t j = 0; j <= m; j++) {
            if (!i || !j) {
                d[i][j] = (int)(i + j);
                continue;
            }
            int best = d[i - 1][j - 1] + (a[i - 1] != b[j - 1]);
            best = d[i - 1][j] + 1 < best ? d[i - 1][j] + 1 : best;
            best = d[i][j - 1] + 1 < best ? d[i][j - 1] + 1 : best;
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] && d[i - 2][j - 2] + 1 < best)
                best = d[i - 2][j - 2] + 1;
            d[i][j] = best;
        }
    return d[n][m] < 9 ? d[n][m] : 9;
}

/* The long option a mistyped name (without "--", len bytes) most likely
 * meant: the nearest within two edits (one for names of up to four
 * letters), else the one it is the start of; NULL when none is close. */
static const char *suggest(const char *name, size_t len)
{
    const char *best = NULL, *prefix_of = NULL;
    int best_d = len <= 4 ? 2 : 3, prefixes = 0;
    for (size_t k = 0; k < N_OPTS; k++) {
        int dist = edit_distance(name, len, OPTS[k].lng);
        if (dist < best_d) {
            best_d = dist;
            best = OPTS[k].lng;
        }
        if (len >= 3 && !strncmp(OPTS[k].lng, name, len)) {
            prefix_of = OPTS[k].lng;
            prefixes++;
        }
    }
    return best ? best : prefixes == 1 ? prefix_of : NULL;
}

/* Features this build may lack: the options that need them, refused with
 * one line that says what to install. */
static int check_features(const rt_options *o, const char *positional, char *err, size_t errlen)
{
    const char *opt = positional ? "scene file" : o->scene_file ? "--scene-file" : o->dump_scene ? "--dump-scene"
                                                : o->stats      ? "--stats"
                                                : o->trace      ? "--trace"
                                                                : NULL;
    if (!RT_HAVE_CJSON && opt) {
        snprintf(err, errlen,
                 "%s: this rt-mpi was built without JSON support (feature 'json'): install cJSON "
                 "(Debian: apt-get install libcjson-dev) and rebuild",
                 opt);
        return RT_EUNSUPPORTED;
    }
    return RT_OK;
}

/* The options of a render, once all are read: the defaults that depend on
 * others (height, roulette) and the combinations that make no sense. 0, or
 * RT_EINVAL with err filled. */
/* Whether option `lng` was on the command line. */
static int given(const rt_options *o, const char *lng)
{
    for (size_t i = 0; i < N_OPTS; i++)
        if (!strcmp(OPTS[i].lng, lng))
            return (int)((o->given >> i) & 1u);
    return 0;
}

/* A named scene's own size, samples and depth (the book's: scenes.h) where
 * the command line gives none; a width alone keeps the scene's aspect. */
static void scene_defaults(rt_options *o)
{
    const rt_scene_info *info = o->scene ? rt_scenes_find(o->scene) : NULL;
    if (!info || !info->width)
        return;
    if (!given(o, "width"))
        o->job.width = info->width;
    if (!given(o, "height")) {
        const uint64_t h = (uint64_t)o->job.width * info->height / info->width;
        o->job.height = h ? (uint32_t)h : 1u;
    }
    if (!given(o, "samples"))
        o->job.samples = info->samples;
    if (!given(o, "max-depth"))
        o->job.max_depth = info->max_depth;
}

static int settle_run(rt_options *o, char *err, size_t errlen)
{
    scene_defaults(o);
    if (!o->job.height) { /* not given (--height is at least 1) */
        o->job.height = (uint32_t)((double)o->job.width / 1.5);
        if (o->job.height == 0) {
            snprintf(err, errlen, "--width: %u gives a height of 0 (width / 1.5); give --height", o->job.width);
            return RT_EINVAL;
        }
    }
    if (o->roulette && o->no_roulette) {
        snprintf(err, errlen, "--roulette and --no-roulette: give one or the other");
        return RT_EINVAL;
    }
    o->job.roulette = o->roulette || (!o->no_roulette && o->job.sampler == RT_SAMPLER_SOBOL);
    o->job.light = o->no_light_sampling ? RT_LIGHT_BRUTE : RT_LIGHT_MIS;
    if (o->no_checkpoint && (o->resume || o->checkpoint)) {
        snprintf(err, errlen, "--no-checkpoint cannot be combined with --resume or --checkpoint");
        return RT_EINVAL;
    }
    if (o->preview && o->passes < 2) {
        snprintf(err, errlen, "--preview: previews are written only with --passes 2 or more");
        return RT_EINVAL;
    }
    if (o->spp_map && !(o->job.noise_threshold > 0.0)) {
        snprintf(err, errlen, "--spp-map: the samples per pixel vary only with --noise-threshold");
        return RT_EINVAL;
    }
    if (o->passes > o->job.samples) {
        snprintf(err, errlen, "--passes: %u passes need at least as many samples (-s %u)", o->passes, o->job.samples);
        return RT_EINVAL;
    }
    if ((uint64_t)o->job.width * o->job.height > MAX_PIXELS) {
        snprintf(err, errlen, "image of %u x %u pixels is too large (at most %llu pixels)", o->job.width, o->job.height,
                 (unsigned long long)MAX_PIXELS);
        return RT_EINVAL;
    }
    return rt_cli_frames_settle(o, err, errlen);
}

rt_cli_action rt_cli_parse(int argc, char **argv, rt_options *o, char *err, size_t errlen)
{
    rt_cli_action action = RT_CLI_RUN;
    const char *positional = NULL; /* the scene file */
    int options_end = 0;           /* after "--", every word is positional */
    if (accel_from_env(o, err, errlen))
        return RT_CLI_ERROR;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        const optdef *d = NULL;
        const char *val = NULL;
        char name[64];
        if (!options_end && !strcmp(arg, "--")) {
            options_end = 1;
            continue;
        }
        if (options_end || arg[0] != '-' || !arg[1]) {
            if (positional) {
                snprintf(err, errlen, "unexpected argument '%s': one scene file only ('%s' is the first; see --help)",
                         arg, positional);
                return RT_CLI_ERROR;
            }
            if (!*arg) {
                snprintf(err, errlen, "scene file: empty file name");
                return RT_CLI_ERROR;
            }
            positional = arg;
            continue;
        }
        if (arg[0] == '-' && arg[1] == '-') {
            const char *eq = strchr(arg + 2, '=');
            size_t len = eq ? (size_t)(eq - arg - 2) : strlen(arg + 2);
            for (size_t k = 0; k < N_OPTS; k++)
                if (strlen(OPTS[k].lng) == len && !strncmp(OPTS[k].lng, arg + 2, len))
                    d = &OPTS[k];
            if (!d) {
                const char *near = suggest(arg + 2, len);
                char hint[64];
                if (near)
                    snprintf(hint, sizeof hint, "did you mean --%s?", near);
                snprintf(err, errlen, "unknown option '%.*s' (%s)", (int)(len + 2), arg, near ? hint : "see --help");
                return RT_CLI_ERROR;
            }
            int takes = d->kind != K_FLAG && d->kind != K_ACTION;
            if (eq) {
                if (!takes) {
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
            int takes = d && d->kind != K_FLAG && d->kind != K_ACTION;
            if (!d || (arg[2] && !takes)) {
                snprintf(err, errlen, "unknown option '%s' (see --help)", arg);
                return RT_CLI_ERROR;
            }
            if (arg[2])
                val = arg + 2; /* -j4 */
            snprintf(name, sizeof name, "-%c", d->shrt);
        }
        if (d->kind != K_FLAG && d->kind != K_ACTION && !val) {
            if (i + 1 >= argc) {
                snprintf(err, errlen, "option %s needs a value", name);
                return RT_CLI_ERROR;
            }
            val = argv[++i];
        }
        if (apply(d, name, val, o, &action, err, errlen))
            return RT_CLI_ERROR;
        o->given |= UINT64_C(1) << (d - OPTS);
    }
    if (action != RT_CLI_RUN)
        return action;
    if (positional && o->scene_file) {
        snprintf(err, errlen, "scene file '%s' and --scene-file %s: give one or the other", positional, o->scene_file);
        return RT_CLI_ERROR;
    }
    if (positional)
        o->scene_file = positional;
    if (o->scene && o->scene_file) {
        snprintf(err, errlen, "--scene and %s: give one or the other", positional ? "a scene file" : "--scene-file");
        return RT_CLI_ERROR;
    }
    if (check_features(o, positional, err, errlen))
        return RT_CLI_ERROR;
    if (!o->scene && !o->scene_file)
        o->scene = "final";
    if (o->dump_scene)
        scene_defaults(o);
    if (o->dump_scene) /* nothing renders: the render's options do not matter */
        return RT_CLI_DUMP_SCENE;
    return settle_run(o, err, errlen) ? RT_CLI_ERROR : RT_CLI_RUN;
}
