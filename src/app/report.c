/* report.c - the trace and stats JSON files (cJSON builds and escapes
 * them), the build's feature list, and UTF-8 cleaning of the strings they
 * record. */
#include "report.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fileio.h"
#include "render.h"
#include "rt_config.h"
#include "status.h"

#if RT_HAVE_CJSON
#include <cJSON.h>
#endif

void rt_report_features(char *buf, size_t n, const char *mpi_library)
{
    snprintf(buf, n, "%sopenmp png%s%s%s%s", strcmp(mpi_library, "none") ? "mpi " : "",
             RT_HAVE_EXR ? " exr" : "", RT_HAVE_CJSON ? " json" : "", RT_HAVE_JPEG ? " jpeg" : "",
#ifdef RT_HAVE_EMBREE
             " embree"
#else
             ""
#endif
    );
}

/* Length of the well-formed UTF-8 sequence at p (1 to 4), or 0. */
static size_t utf8_seq(const unsigned char *p)
{
    if (p[0] < 0x80)
        return 1;
    size_t len = p[0] >= 0xC2 && p[0] <= 0xDF ? 2 : p[0] >= 0xE0 && p[0] <= 0xEF ? 3 : p[0] >= 0xF0 && p[0] <= 0xF4 ? 4 : 0;
    /* the second byte's range excludes overlong forms, surrogates
     * (ED A0..BF) and code points beyond U+10FFFF (F4 90..) */
    unsigned char lo = p[0] == 0xE0 ? 0xA0 : p[0] == 0xF0 ? 0x90 : 0x80;
    unsigned char hi = p[0] == 0xED ? 0x9F : p[0] == 0xF4 ? 0x8F : 0xBF;
    if (!len || p[1] < lo || p[1] > hi)
        return 0;
    for (size_t i = 2; i < len; i++) /* a NUL ends the loop too: it is no continuation byte */
        if ((p[i] & 0xC0) != 0x80)
            return 0;
    return len;
}

char *rt_report_utf8(const char *s)
{
    const unsigned char *p = (const unsigned char *)s;
    size_t n = strlen(s);
    char *out = malloc(3 * n + 1); /* each byte at worst becomes EF BF BD */
    if (!out)
        return NULL;
    size_t o = 0;
    while (*p) {
        size_t len = utf8_seq(p);
        if (len) {
            memcpy(out + o, p, len);
            o += len;
            p += len;
        } else {
            memcpy(out + o, "\xEF\xBF\xBD", 3);
            o += 3;
            p++;
        }
    }
    out[o] = 0;
    return out;
}

#if RT_HAVE_CJSON

/* Builders that remember a failed allocation in *ok: the document is built
 * whole and written only if nothing failed. */
static cJSON *add(cJSON *parent, const char *key, cJSON *item, int *ok)
{
    if (!item) {
        *ok = 0;
        return NULL;
    }
    if (!(key ? cJSON_AddItemToObject(parent, key, item) : cJSON_AddItemToArray(parent, item))) {
        cJSON_Delete(item);
        *ok = 0;
        return NULL;
    }
    return item;
}

static void add_str(cJSON *parent, const char *key, const char *value, int *ok)
{
    char *clean = rt_report_utf8(value);
    add(parent, key, clean ? cJSON_CreateString(clean) : NULL, ok);
    free(clean);
}

static void add_num(cJSON *parent, const char *key, double v, int *ok) { add(parent, key, cJSON_CreateNumber(v), ok); }

/* Whole numbers beyond 2^53 (seeds, segment counts) as written, not
 * rounded through a double. */
static void add_u64(cJSON *parent, const char *key, uint64_t v, int *ok)
{
    char buf[24];
    snprintf(buf, sizeof buf, "%" PRIu64, v);
    add(parent, key, cJSON_CreateRaw(buf), ok);
}

static void add_hex(cJSON *parent, const char *key, uint64_t v, int *ok)
{
    char buf[24];
    snprintf(buf, sizeof buf, "%016" PRIx64, v);
    add_str(parent, key, buf, ok);
}

/* Microseconds to the nearest nanosecond, as the trace had them. */
static double usec(double seconds) { return round(seconds * 1e9) / 1e3; }

/* The provenance both reports carry. */
static void add_origin(cJSON *o, const rt_report_origin *g, int *ok)
{
    char features[96], when[32] = "";
    rt_report_features(features, sizeof features, g->mpi_library);
    add_str(o, "version", RT_VERSION, ok);
    add_num(o, "sampling_version", RT_RENDER_SAMPLING, ok);
    cJSON *f = add(o, "features", cJSON_CreateArray(), ok);
    char *save = NULL;
    for (char *w = strtok_r(features, " ", &save); f && w; w = strtok_r(NULL, " ", &save))
        add_str(f, NULL, w, ok);
    cJSON *argv = add(o, "command_line", cJSON_CreateArray(), ok);
    for (int i = 0; argv && i < g->argc; i++)
        add_str(argv, NULL, g->argv[i], ok);
    struct tm tm;
    if (gmtime_r(&g->start, &tm))
        strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", &tm);
    add_str(o, "start_time", when, ok);
    add_str(o, "host", g->host ? g->host : "", ok);
    add_str(o, "mpi_library", g->mpi_library ? g->mpi_library : "none", ok);
    if (g->slurm_job_id)
        add_str(o, "slurm_job_id", g->slurm_job_id, ok);
}

/* The document into path, atomically; frees doc. */
static int write_doc(const char *path, cJSON *doc, int ok, int formatted)
{
    char *text = ok ? (formatted ? cJSON_Print(doc) : cJSON_PrintUnformatted(doc)) : NULL;
    cJSON_Delete(doc);
    if (!text)
        return RT_ENOMEM;
    rt_atomic_file f;
    int st = rt_atomic_open(&f, path);
    if (!st) {
        size_t n = strlen(text);
        if (fwrite(text, 1, n, f.fp) != n || fputc('\n', f.fp) == EOF) {
            st = rt_status_from_errno(errno);
            rt_atomic_abort(&f);
        } else {
            st = rt_atomic_commit(&f);
        }
    }
    free(text);
    return st;
}

int rt_report_trace(const char *path, const rt_trace_event *ev, size_t n, int ranks, const rt_report_origin *origin)
{
    int ok = 1;
    cJSON *doc = cJSON_CreateObject();
    if (!doc)
        return RT_ENOMEM;
    add_str(doc, "displayTimeUnit", "ms", &ok);
    /* the trace-event format's place for anything else */
    cJSON *other = add(doc, "otherData", cJSON_CreateObject(), &ok);
    if (other)
        add_origin(other, origin, &ok);
    cJSON *events = add(doc, "traceEvents", cJSON_CreateArray(), &ok);
    for (int r = 0; events && r < ranks; r++) {
        cJSON *e = add(events, NULL, cJSON_CreateObject(), &ok), *args;
        char name[32];
        snprintf(name, sizeof name, "rank %d", r);
        if (!e)
            break;
        add_str(e, "name", "process_name", &ok);
        add_str(e, "ph", "M", &ok);
        add_num(e, "pid", r, &ok);
        add_num(e, "tid", 0, &ok);
        if ((args = add(e, "args", cJSON_CreateObject(), &ok)))
            add_str(args, "name", name, &ok);
    }
    for (size_t i = 0; events && ok && i < n; i++) {
        const rt_trace_event *t = &ev[i];
        cJSON *e = add(events, NULL, cJSON_CreateObject(), &ok), *args;
        char name[80];
        if (!e)
            break;
        snprintf(name, sizeof name, "rows %u-%u x %u-%u s %u-%u", t->unit.y0, t->unit.y1, t->unit.x0, t->unit.x1,
                 t->unit.s0, t->unit.s1);
        add_str(e, "name", name, &ok);
        add_str(e, "cat", "unit", &ok);
        add_str(e, "ph", "X", &ok);
        add_num(e, "pid", t->rank, &ok);
        add_num(e, "tid", 0, &ok);
        add_num(e, "ts", usec(t->start), &ok);
        add_num(e, "dur", usec(t->end - t->start), &ok);
        if ((args = add(e, "args", cJSON_CreateObject(), &ok))) {
            add_num(args, "unit", t->unit.id, &ok);
            add_num(args, "y0", t->unit.y0, &ok);
            add_num(args, "y1", t->unit.y1, &ok);
            add_num(args, "x0", t->unit.x0, &ok);
            add_num(args, "x1", t->unit.x1, &ok);
            add_num(args, "s0", t->unit.s0, &ok);
            add_num(args, "s1", t->unit.s1, &ok);
        }
    }
    return write_doc(path, doc, ok, 0);
}

int rt_report_stats(const char *path, const rt_run_summary *s)
{
    int ok = 1;
    cJSON *doc = cJSON_CreateObject();
    if (!doc)
        return RT_ENOMEM;
    add_str(doc, "output", s->output, &ok);
    if (s->frame_job) {
        add_num(doc, "frame", s->frame, &ok);
        add_num(doc, "frames_held_peak", s->frames_peak, &ok);
        add_num(doc, "render_start_seconds", s->frame_start, &ok);
    }
    add_num(doc, "width", s->job->width, &ok);
    add_num(doc, "height", s->job->height, &ok);
    add_num(doc, "samples", s->job->samples, &ok);
    add_num(doc, "max_depth", s->job->max_depth, &ok);
    add_u64(doc, "seed", s->job->seed, &ok);
    add_str(doc, "diffuse", rt_diffuse_name(s->job->diffuse), &ok);
    add_str(doc, "sampler", rt_sampler_name(s->job->sampler), &ok);
    add(doc, "roulette", cJSON_CreateBool(s->job->roulette), &ok);
    add_hex(doc, "scene_hash", s->scene_hash, &ok);
    add_hex(doc, "image_hash", s->image_hash, &ok);
    add_str(doc, "intersector", s->intersector, &ok);
    add_num(doc, "ranks", s->ranks, &ok);
    add_num(doc, "threads_per_rank", s->threads, &ok);
    add(doc, "mpi", cJSON_CreateBool(s->mpi), &ok);
    add_num(doc, "units", s->units, &ok);
    add_num(doc, "rows_restored", s->rows_restored, &ok);
    add_num(doc, "render_seconds", s->wall, &ok);
    add_num(doc, "total_seconds", s->total_wall, &ok);
    add_num(doc, "setup_seconds", s->setup, &ok);
    add_u64(doc, "ray_segments", s->segments, &ok);
    add_num(doc, "segments_per_second", s->wall > 0 ? (double)s->segments / s->wall : 0.0, &ok);
    if (s->spp) {
        cJSON *a = cJSON_CreateObject(), *by = cJSON_CreateObject();
        add(doc, "adaptive", a, &ok);
        add_num(a, "noise_threshold", s->job->noise_threshold, &ok);
        add_num(a, "mean_samples_per_pixel", s->spp->mean, &ok);
        add(a, "pixels_by_samples", by, &ok);
        for (uint32_t k = 0; k < s->spp->n_levels; k++) {
            char key[16];
            snprintf(key, sizeof key, "%u", s->spp->count[k]);
            add_u64(by, key, s->spp->pixels[k], &ok);
        }
    }
    add_origin(doc, &s->origin, &ok);
    if (s->farm) {
        add_u64(doc, "rank0_messages_in", s->farm->msgs_in, &ok);
        add_u64(doc, "rank0_bytes_in", s->farm->bytes_in, &ok);
        add_num(doc, "rank0_serve_cpu_seconds", s->farm->serve_cpu, &ok);
        add_num(doc, "final_combine_seconds", s->farm->final_combine, &ok);
        add_num(doc, "lost_ranks", s->farm->lost, &ok);
    }
    cJSON *ranks = add(doc, "per_rank", cJSON_CreateArray(), &ok);
    for (int r = 0; ranks && s->per_rank && r < s->ranks; r++) {
        const rt_rank_stats *x = &s->per_rank[r];
        double idle = s->wall - x->busy - x->comm;
        cJSON *e = add(ranks, NULL, cJSON_CreateObject(), &ok);
        if (!e)
            break;
        add_num(e, "rank", r, &ok);
        add_str(e, "host", x->host, &ok);
        add_num(e, "units", x->units, &ok);
        add_num(e, "rows", x->rows, &ok);
        add_num(e, "segments", x->segments, &ok);
        add_num(e, "busy_seconds", x->busy, &ok);
        add_num(e, "wait_seconds", x->wait, &ok);
        add_num(e, "comm_seconds", x->comm, &ok);
        add_num(e, "idle_seconds", idle < 0 ? 0 : idle, &ok);
        add_num(e, "peak_rss_mb", x->maxrss_mb, &ok);
        add_num(e, "held_mb", x->held_mb, &ok);
        add(e, "lost", cJSON_CreateBool(x->lost), &ok);
        if (x->lost) {
            add_num(e, "lost_at_seconds", x->lost_at, &ok);
            add_num(e, "silent_seconds", x->silent, &ok);
            add_num(e, "units_redone", x->units_redone, &ok);
            add_num(e, "redone_seconds", x->redone, &ok);
        }
    }
    return write_doc(path, doc, ok, 1);
}

#else /* built without cJSON */

int rt_report_trace(const char *path, const rt_trace_event *ev, size_t n, int ranks, const rt_report_origin *origin)
{
    (void)path, (void)ev, (void)n, (void)ranks, (void)origin;
    return RT_EUNSUPPORTED;
}

int rt_report_stats(const char *path, const rt_run_summary *s)
{
    (void)path, (void)s;
    return RT_EUNSUPPORTED;
}

#endif
