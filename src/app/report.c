/* report.c - trace and stats JSON writers. */
#include "report.h"

#include <inttypes.h>
#include <stdio.h>

#include "fileio.h"
#include "status.h"

int rt_report_trace(const char *path, const rt_trace_event *ev, size_t n, int ranks)
{
    rt_atomic_file f;
    int st = rt_atomic_open(&f, path);
    if (st)
        return st;
    FILE *fp = f.fp;
    fprintf(fp, "{\"displayTimeUnit\":\"ms\",\"traceEvents\":[\n");
    for (int r = 0; r < ranks; r++)
        fprintf(fp, "{\"name\":\"process_name\",\"ph\":\"M\",\"pid\":%d,\"tid\":0,\"args\":{\"name\":\"rank %d\"}},\n", r,
                r);
    for (size_t i = 0; i < n; i++) {
        const rt_trace_event *e = &ev[i];
        fprintf(fp,
                "{\"name\":\"rows %u-%u s %u-%u\",\"cat\":\"unit\",\"ph\":\"X\",\"pid\":%d,\"tid\":0,"
                "\"ts\":%.3f,\"dur\":%.3f,\"args\":{\"unit\":%u,\"y0\":%u,\"y1\":%u,\"s0\":%u,\"s1\":%u}}%s\n",
                e->unit.y0, e->unit.y1, e->unit.s0, e->unit.s1, e->rank, e->start * 1e6, (e->end - e->start) * 1e6,
                e->unit.id, e->unit.y0, e->unit.y1, e->unit.s0, e->unit.s1, i + 1 < n ? "," : "");
    }
    fprintf(fp, "]}\n");
    return rt_atomic_commit(&f);
}

int rt_report_stats(const char *path, const rt_run_summary *s)
{
    rt_atomic_file f;
    int st = rt_atomic_open(&f, path);
    if (st)
        return st;
    FILE *fp = f.fp;
    fprintf(fp, "{\n  \"output\": \"");
    for (const char *p = s->output; *p; p++) {
        if (*p == '"' || *p == '\\')
            fputc('\\', fp);
        if ((unsigned char)*p >= 0x20)
            fputc(*p, fp);
    }
    fprintf(fp, "\",\n");
    fprintf(fp, "  \"width\": %u, \"height\": %u, \"samples\": %u, \"max_depth\": %u,\n", s->job->width,
            s->job->height, s->job->samples, s->job->max_depth);
    fprintf(fp, "  \"seed\": %" PRIu64 ", \"scene_hash\": \"%016" PRIx64 "\", \"image_hash\": \"%016" PRIx64 "\",\n",
            s->job->seed, s->scene_hash, s->image_hash);
    fprintf(fp, "  \"intersector\": \"%s\", \"ranks\": %d, \"threads_per_rank\": %d, \"mpi\": %s,\n",
            s->intersector, s->ranks, s->threads, s->mpi ? "true" : "false");
    fprintf(fp, "  \"units\": %u, \"rows_restored\": %u,\n", s->units, s->rows_restored);
    fprintf(fp, "  \"render_seconds\": %.6f, \"total_seconds\": %.6f,\n", s->wall, s->total_wall);
    fprintf(fp, "  \"ray_segments\": %" PRIu64 ", \"segments_per_second\": %.1f,\n", s->segments,
            s->wall > 0 ? (double)s->segments / s->wall : 0.0);
    fprintf(fp,
            "  \"rank0_messages_in\": %" PRIu64 ", \"rank0_bytes_in\": %" PRIu64 ", \"rank0_serve_cpu_seconds\": %.6f, "
            "\"final_combine_seconds\": %.6f, \"lost_ranks\": %d,\n",
            s->farm->msgs_in, s->farm->bytes_in, s->farm->serve_cpu, s->farm->final_combine, s->farm->lost);
    fprintf(fp, "  \"per_rank\": [\n");
    for (int r = 0; r < s->ranks; r++) {
        const rt_rank_stats *x = &s->per_rank[r];
        double idle = s->wall - x->busy - x->comm;
        fprintf(fp,
                "    {\"rank\": %d, \"units\": %.0f, \"rows\": %.3f, \"segments\": %.0f, \"busy_seconds\": %.6f, "
                "\"wait_seconds\": %.6f, \"comm_seconds\": %.6f, \"idle_seconds\": %.6f, \"peak_rss_mb\": %.1f, "
                "\"held_mb\": %.3f, \"lost\": %s}%s\n",
                r, x->units, x->rows, x->segments, x->busy, x->wait, x->comm, idle < 0 ? 0 : idle, x->maxrss_mb,
                x->held_mb, x->lost ? "true" : "false",
                r + 1 < s->ranks ? "," : "");
    }
    fprintf(fp, "  ]\n}\n");
    return rt_atomic_commit(&f);
}
