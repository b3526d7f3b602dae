/* test_checkpoint.c - checkpoint round trip; a checkpoint of another job is
 * refused naming the field; corruption and truncation are caught by the
 * checksum; nothing is left behind by a failed write. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "checkpoint.h"
#include "status.h"

int main(void)
{
    char dir[] = "/tmp/rt-ckpt-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256];
    snprintf(path, sizeof path, "%s/c.ckpt", dir);
    const uint32_t W = 5, H = 7;
    rt_ckpt_id job = {.job = {.width = W,
                              .height = H,
                              .samples = 16,
                              .max_depth = 50,
                              .seed = 42,
                              .diffuse = RT_DIFFUSE_LAMBERTIAN,
                              .sampler = RT_SAMPLER_SOBOL,
                              .roulette = 1},
                      .exact = 1,
                      .scene_hash = 0x1234,
                      .sampling = 2};
    int64_t acc[5 * 7 * 3], back[5 * 7 * 3];
    uint32_t done[7] = {16, 0, 16, 5, 0, 0, 16}, done2[7]; /* samples per row */
    for (int i = 0; i < 5 * 7 * 3; i++)
        acc[i] = (int64_t)i * 1000003 - 7;
    CHECK_EQ_INT(rt_ckpt_write(path, &job, done, acc), RT_OK);
    char why[256];
    uint32_t n = 0;
    memset(back, 0x55, sizeof back);
    CHECK_EQ_INT(rt_ckpt_read(path, &job, done2, back, &n, why, sizeof why), RT_OK);
    CHECK_EQ_INT(n, 3); /* complete rows */
    CHECK(memcmp(done, done2, sizeof done) == 0);
    int rows_ok = 1;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t i = 0; i < W * 3; i++)
            rows_ok &= back[y * W * 3 + i] == (done[y] ? acc[y * W * 3 + i] : 0);
    CHECK(rows_ok);

    /* Each field of the job identity, changed alone, is refused by name
     * with the checkpoint's value. */
    struct {
        const char *says;
        rt_ckpt_id id;
    } others[24];
    for (size_t k = 0; k < 24; k++)
        others[k].id = job;
    size_t n_others = 0;
#define OTHER(what, field, value) (others[n_others].says = (what), others[n_others++].id.field = (value))
    OTHER("(width 5,", job.width, W + 1);
    OTHER("(height 7,", job.height, H - 1);
    OTHER("(samples 16,", job.samples, 17);
    OTHER("(max depth 50,", job.max_depth, 5);
    OTHER("(diffuse model 0,", job.diffuse, RT_DIFFUSE_HEMISPHERE);
    OTHER("(intersector 1,", exact, 0);
    OTHER("(seed 42,", job.seed, 43);
    OTHER("(scene 4660,", scene_hash, 1);
    OTHER("(sampling version 2,", sampling, 3); /* a build that samples differently */
    OTHER("(sampler 1,", job.sampler, RT_SAMPLER_RANDOM);
    OTHER("(roulette 1,", job.roulette, 0);
    OTHER("(denoiser buffers (--aov) 0,", job.aov, RT_AOV_ALBEDO);
    OTHER("(noise threshold (bits) 0,", job.noise_threshold, 0.05);
    OTHER("(light sampling (0 on, 1 off) 0,", job.light, 1);
    OTHER("(frame job (--frames, --frame) 0,", frame_job, 1); /* a frame job's: zeros for one image */
    OTHER("(first frame 0,", first, 1);
    OTHER("(last frame 0,", last, 3);
    OTHER("(frame step 0,", step, 2);
    OTHER("(turntable frames 0,", turn_frames, 48);
    OTHER("(turntable degrees (bits) 0,", turn_degrees, 360.0);
#undef OTHER
    CHECK_EQ_INT(n_others, 20); /* every field rt_ckpt_read compares */
    for (size_t k = 0; k < n_others; k++) {
        why[0] = 0;
        CHECK_EQ_INT(rt_ckpt_read(path, &others[k].id, done2, back, &n, why, sizeof why), RT_EMISMATCH);
        CHECK_HAS(why, others[k].says);
        why[0] = 0; /* the identity alone (a frame job's resume) says the same */
        CHECK_EQ_INT(rt_ckpt_check(path, &others[k].id, why, sizeof why), RT_EMISMATCH);
        CHECK_HAS(why, others[k].says);
    }
    CHECK_EQ_INT(rt_ckpt_check(path, &job, why, sizeof why), RT_OK);

    /* A frame job's checkpoint names the frames it holds, each with its
     * rows' counts and sums (format 8: several frames in flight). */
    {
        rt_ckpt_id fr = job;
        fr.frame_job = 1, fr.first = 2, fr.last = 8, fr.step = 3, fr.frame = 5;
        fr.turn_frames = 12, fr.turn_degrees = 90.0;
        char fpath[600];
        snprintf(fpath, sizeof fpath, "%s/frames.ckpt", dir);
        CHECK_EQ_INT(rt_ckpt_write(fpath, &fr, done, acc), RT_OK);
        uint32_t frames[4] = {0}, nf = 0;
        CHECK_EQ_INT(rt_ckpt_frames(fpath, &nf, frames, 4, why, sizeof why), RT_OK);
        CHECK_EQ_INT(nf, 1);
        CHECK_EQ_INT(frames[0], 5);
        CHECK_EQ_INT(rt_ckpt_check(fpath, &fr, why, sizeof why), RT_OK);
        CHECK_EQ_INT(rt_ckpt_read(fpath, &fr, done2, back, &n, why, sizeof why), RT_OK);
        CHECK(memcmp(done, done2, sizeof done) == 0);
        CHECK_EQ_INT(rt_ckpt_frames(path, &nf, frames, 4, why, sizeof why), RT_OK); /* one image's: frame 0 */
        CHECK_EQ_INT(nf, 1);
        CHECK_EQ_INT(frames[0], 0);
        /* two frames: 8 and 2, the second with its own counts and sums */
        int64_t acc2[5 * 7 * 3], back2[5 * 7 * 3];
        for (int i = 0; i < 5 * 7 * 3; i++)
            acc2[i] = -(int64_t)i * 77 + 3;
        uint32_t two[14], two_back[14];
        for (int y = 0; y < 7; y++)
            two[y] = done[y], two[7 + y] = (uint32_t)(y % 3) * 4;
        const uint32_t numbers[2] = {8, 2};
        const int64_t *const accs[2] = {acc, acc2};
        CHECK_EQ_INT(rt_ckpt_write_frames(fpath, &fr, 2, numbers, two, accs), RT_OK);
        CHECK_EQ_INT(rt_ckpt_frames(fpath, &nf, frames, 4, why, sizeof why), RT_OK);
        CHECK_EQ_INT(nf, 2);
        CHECK_EQ_INT(frames[0], 8);
        CHECK_EQ_INT(frames[1], 2);
        CHECK_EQ_INT(rt_ckpt_frames(fpath, &nf, frames, 1, why, sizeof why), RT_EFORMAT); /* no room */
        CHECK_EQ_INT(rt_ckpt_read(fpath, &fr, done2, back, &n, why, sizeof why), RT_EFORMAT); /* not one frame */
        memset(back2, 0x55, sizeof back2);
        int64_t *const outs[2] = {back, back2};
        CHECK_EQ_INT(rt_ckpt_read_frames(fpath, &fr, 2, two_back, outs, &n, why, sizeof why), RT_OK);
        CHECK(memcmp(two, two_back, sizeof two) == 0);
        CHECK_EQ_INT(n, 3); /* complete rows: frame 8's three */
        int both = 1;
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t i = 0; i < W * 3; i++)
                both &= back[y * W * 3 + i] == (done[y] ? acc[y * W * 3 + i] : 0) &&
                        back2[y * W * 3 + i] == (two[7 + y] ? acc2[y * W * 3 + i] : 0);
        CHECK(both);
        unlink(fpath);
    }

    /* A wide layout (adaptive count and both buffers: 10 values a pixel)
     * round-trips whole rows. */
    {
        rt_ckpt_id wide = job;
        wide.job.noise_threshold = 0.02;
        wide.job.aov = RT_AOV_ALBEDO | RT_AOV_NORMAL;
        CHECK_EQ_INT(rt_job_layout(&wide.job).ch, 10);
        int64_t wa[5 * 7 * 10], wb[5 * 7 * 10];
        for (int i = 0; i < 5 * 7 * 10; i++)
            wa[i] = (int64_t)i * 7919 - 300;
        CHECK_EQ_INT(rt_ckpt_write(path, &wide, done, wa), RT_OK);
        CHECK_EQ_INT(rt_ckpt_read(path, &wide, done2, wb, &n, why, sizeof why), RT_OK);
        int wide_ok = 1;
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t i = 0; i < W * 10; i++)
                wide_ok &= wb[y * W * 10 + i] == (done[y] ? wa[y * W * 10 + i] : 0);
        CHECK(wide_ok);
        CHECK_EQ_INT(rt_ckpt_read(path, &job, done2, back, &n, why, sizeof why), RT_EMISMATCH);
        CHECK_EQ_INT(rt_ckpt_write(path, &job, done, acc), RT_OK); /* as the rest expects */
    }

    /* A sample count above the job's is refused even with a valid checksum. */
    uint32_t over[7] = {17, 0, 0, 0, 0, 0, 0};
    char odd[256];
    snprintf(odd, sizeof odd, "%s/odd.ckpt", dir);
    CHECK_EQ_INT(rt_ckpt_write(odd, &job, over, acc), RT_OK);
    CHECK_EQ_INT(rt_ckpt_read(odd, &job, done2, back, &n, why, sizeof why), RT_EFORMAT);
    unlink(odd);

    /* Corruption anywhere and truncation are refused. */
    FILE *fp = fopen(path, "rb");
    unsigned char buf[4096];
    size_t len = fread(buf, 1, sizeof buf, fp);
    fclose(fp);
    int refused = 1;
    char bad[256];
    snprintf(bad, sizeof bad, "%s/bad.ckpt", dir);
    for (size_t i = 8; i < len; i += 5) {
        buf[i] ^= 0x10;
        fp = fopen(bad, "wb");
        fwrite(buf, 1, len, fp);
        fclose(fp);
        buf[i] ^= 0x10;
        int st = rt_ckpt_read(bad, &job, done2, back, &n, why, sizeof why);
        refused &= st == RT_ECHECKSUM;
    }
    CHECK(refused);
    fp = fopen(bad, "wb");
    fwrite(buf, 1, len - 9, fp);
    fclose(fp);
    CHECK_EQ_INT(rt_ckpt_read(bad, &job, done2, back, &n, why, sizeof why), RT_ECHECKSUM);
    fp = fopen(bad, "wb");
    fputs("hello, not a checkpoint", fp);
    fclose(fp);
    CHECK_EQ_INT(rt_ckpt_read(bad, &job, done2, back, &n, why, sizeof why), RT_EFORMAT);
    snprintf(bad, sizeof bad, "%s/missing.ckpt", dir);
    CHECK_EQ_INT(rt_ckpt_read(bad, &job, done2, back, &n, why, sizeof why), RT_EIO);
    /* A write into a missing directory fails and creates nothing. */
    snprintf(bad, sizeof bad, "%s/no/such.ckpt", dir);
    CHECK(rt_ckpt_write(bad, &job, done, acc) != RT_OK);
    char cmd[512];
    snprintf(cmd, sizeof cmd, "test $(ls %s | wc -l) -eq 2 && rm -rf %s", dir, dir);
    CHECK_EQ_INT(system(cmd), 0);
    CHECK_DONE();
}
