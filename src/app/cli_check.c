/* cli_check.c - the command line's checks that other parts of the app share:
 * a decimal number in a range, and a file the run will write (an image of a
 * supported format with options that fit it, or any file, in a writable
 * directory). Below cli.c and cli_frames.c, which both call it. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "fileio.h"
#include "image_write.h"
#include "status.h"

int rt_cli_parse_u64(const char *s, uint64_t lo, uint64_t hi, uint64_t *out)
{
    if (!s || !*s)
        return RT_EINVAL;
    uint64_t v = 0;
    for (const char *p = s; *p; p++) {
        if (*p < '0' || *p > '9')
            return RT_EINVAL;
        unsigned d = (unsigned)(*p - '0');
        if (v > (UINT64_MAX - d) / 10)
            return RT_ERANGE;
        v = v * 10 + d;
    }
    if (v < lo || v > hi)
        return RT_ERANGE;
    *out = v;
    return RT_OK;
}

/* The file can be created: a file name, in a writable directory. */
int rt_cli_check_path(const char *opt, const char *path, char *err, size_t errlen)
{
    const char *slash = strrchr(path, '/');
    if (!*(slash ? slash + 1 : path)) {
        snprintf(err, errlen, "%s: '%s' names a directory, not a file", opt, path);
        return RT_EINVAL;
    }
    int st = rt_file_check_writable(path);
    if (st == RT_EINVAL)
        snprintf(err, errlen, "%s: '%s' is a directory", opt, path);
    else if (st)
        snprintf(err, errlen, "%s: cannot write '%s': %s", opt, path, rt_status_str(st));
    return st;
}

/* An image path: supported extension, options that fit its format, and a
 * file that can be created. */
static int check_image_path(const char *opt, const char *path, const rt_options *o, char *err, size_t errlen)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    rt_image_format fmt = rt_image_format_from_path(path);
    rt_image_write_opts wo = {.bit_depth = o->bit_depth, .ppm_ascii = o->ppm_ascii};
    if (*base && fmt == RT_FORMAT_UNKNOWN) {
        snprintf(err, errlen, "%s: unsupported file type '%s' (supported: %s)", opt, dot ? dot : base,
                 rt_image_format_list());
        return RT_EINVAL;
    }
    if (*base && !rt_image_format_available(fmt)) { /* only .exr can be missing */
        snprintf(err, errlen,
                 "%s '%s': this rt-mpi was built without OpenEXR (feature 'exr'): install OpenEXR 3 "
                 "(Debian: apt-get install libopenexr-dev) and rebuild, or write .pfm",
                 opt, path);
        return RT_EUNSUPPORTED;
    }
    if (*base && rt_image_check_opts(fmt, &wo) != RT_OK) {
        if (o->ppm_ascii && fmt != RT_FORMAT_PPM)
            snprintf(err, errlen, "--ppm-ascii: %s '%s' is not a .ppm file", opt, path);
        else
            snprintf(err, errlen, "--bit-depth %d: %s files are written %s", o->bit_depth, dot,
                     fmt == RT_FORMAT_BMP ? "with 8 bits per channel only" : "as 32-bit float");
        return RT_EINVAL;
    }
    return rt_cli_check_path(opt, path, err, errlen);
}

int rt_cli_check_output(const rt_options *o, char *err, size_t errlen)
{
    if (check_image_path("--output", o->output, o, err, errlen))
        return RT_EINVAL;
    if (o->spp_map && check_image_path("--spp-map", o->spp_map, o, err, errlen))
        return RT_EINVAL;
    if (o->done_file && rt_cli_check_path("--done-file", o->done_file, err, errlen))
        return RT_EINVAL;
    return o->preview ? check_image_path("--preview", o->preview, o, err, errlen) : 0;
}
