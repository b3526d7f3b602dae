/* usage.c - the help text (rt_cli_usage, cli.h), apart from the option
 * parser: one string per section, in the help's order. The farm's defaults
 * come from policy.h and the exit status section from the exit-code table
 * (exitcode.h), so neither is a copy. Also the man page's source
 * (cmake/help2man.awk): a line "Topic:" opens a section, "  -x, --opt <ARG>
 * text" an item, deeper lines go on. */
#include "cli.h"

#include <stdio.h>
#include <string.h>

#include "exitcode.h"
#include "policy.h"

static const char intro[] =
    "Usage: rt-mpi [OPTIONS] [SCENE.json]\n"
    "       mpirun -np N rt-mpi [OPTIONS] [SCENE.json]\n"
    "\n"
    "Renders the \"Ray Tracing in One Weekend\" scenes, or a JSON scene file, with a\n"
    "path tracer that spreads row bands over MPI ranks and OpenMP threads. The image\n"
    "is byte-identical for any number of ranks, threads and any band size. Progress\n"
    "goes to stderr, the run summary (with the image hash) to stdout.\n";

static const char output[] =
    "Output:\n"
    "  -o, --output <FILE>      Output image; the extension picks the format: .png, .ppm,\n"
    "                           .bmp, or .pfm/.exr (linear float) [default: output.png]\n"
    "      --bit-depth <BITS>   8 or 16 bits per channel (.png and .ppm) [default: 8]\n"
    "      --ppm-ascii          Write .ppm as ASCII P3, as the book does (default: binary P6)\n"
    "      --aov <LIST>         Also write what a denoiser needs: albedo, normal or both\n"
    "                           (albedo,normal), as OUTPUT.albedo.pfm and OUTPUT.normal.pfm\n"
    "                           (.exr beside an .exr output): the first non-specular hit,\n"
    "                           averaged over the pixel's samples\n"
    "  -q, --quiet              No progress output on stderr\n";

static const char scene[] =
    "Scene:\n"
    "  SCENE.json               A JSON scene file: the same as --scene-file SCENE.json\n"
    "      --scene <NAME>       Scene to render (see --list-scenes) [default: final]\n"
    "      --scene-file <FILE>  Render the scene described by a JSON scene file instead\n"
    "      --list-scenes        List the named scenes and exit\n"
    "      --dump-scene <FILE>  Write the scene this run would render as JSON, then exit\n"
    "      --texture-dir <DIR>  Where the scenes with the earth (earth, book2-final) read\n"
    "                           earthmap.jpg, from the book's repository [default: .]\n"
    "      --grid <GRID>        Half-grid size N of the final scene: 2N x 2N small spheres\n"
    "                           [default: 11]\n"
    "      --width <WIDTH>      Image width in pixels [default: 1200; book 2's scenes:\n"
    "                           the book's]\n"
    "      --height <HEIGHT>    Image height in pixels (default: width / 1.5; book 2's\n"
    "                           scenes: the book's aspect)\n";

static const char sampling[] =
    "Sampling:\n"
    "  -s, --samples <SAMPLES>  Samples per pixel [default: 500]\n"
    "      --seed <SEED>        Scene and sampling seed [default: 42]\n"
    "      --max-depth <DEPTH>  Maximum ray segments per path [default: 50]\n"
    "      --diffuse <MODEL>    lambertian, sphere or hemisphere [default: lambertian]\n"
    "      --sampler <NAME>     sobol (scrambled Sobol points: less noise for the same\n"
    "                           samples) or random (independent random numbers: the images\n"
    "                           of sampling version 2) [default: sobol]\n"
    "      --roulette           Russian roulette (unbiased) of dim paths after 3 bounces\n"
    "                           [default: on with sobol, off with random]\n"
    "      --no-roulette        No Russian roulette\n"
    "      --no-light-sampling  Scenes with emitters: find them only by chance (book 2's\n"
    "                           brute-force paths) instead of sampling them at diffuse\n"
    "                           surfaces and media (next-event estimation with MIS)\n"
    "      --noise-threshold <X>  Adaptive sampling: 16 pilot samples of its own decide how\n"
    "                           many samples a pixel takes (16, 32, 64, ..., at most -s)\n"
    "                           for an estimated relative error of X (0.01 to 0.05)\n"
    "                           [default: off]\n"
    "      --spp-map <FILE>     With --noise-threshold: write each pixel's samples over -s\n"
    "                           as an image (gamma 2 in PNG, PPM, BMP; linear in PFM, EXR)\n"
    "      --passes <K>         Progressive: render the samples in K passes over the whole\n"
    "                           image, rewriting a preview after each [default: 1]\n"
    "      --preview <FILE>     Preview image of --passes [default: the output]\n"
    "      --shutter <OPEN,CLOSE>  Rays' time in [frame + OPEN, frame + CLOSE), fractions\n"
    "                           of a frame, 0 <= OPEN <= CLOSE <= 1 (0,0: no motion blur)\n"
    "                           [default: 0,1 for scenes with moving spheres, else 0,0]\n";

static const char parallel[] =
    "Parallel:\n"
    "  -j, --threads <THREADS>  Threads per rank (0 = OMP_NUM_THREADS if set, else all\n"
    "                           cores available to the rank) [default: 0]\n"
    "      --band <ROWS>        Rows per work unit (0 = automatic) [default: 0]\n"
    "      --lease <SECONDS>    A rank that rank 0 has not heard from for this long is lost: its\n"
    "                           units go to the others [default: " RT_POLICY_STR(RT_POLICY_LEASE) "]\n"
    "      --split <HOW>        When rows are fewer than the ranks want: columns (tiles: each\n"
    "                           pixel's sums travel once) or samples [default: columns]\n"
    "      --flush-interval <SECONDS>  A rank sends its sums at least this often (0: only when\n"
    "                           rank 0 asks or it holds --flush-mb) [default: " RT_POLICY_STR(RT_POLICY_FLUSH_INTERVAL) "]\n"
    "      --flush-mb <MB>      A rank sends its sums once it holds this many [default: " RT_POLICY_STR(RT_POLICY_FLUSH_MB) "]\n";

static const char frames[] =
    "Frames (one job renders a sequence):\n"
    "      --frames <A-B[:STEP]>  Render frames A to B (every STEP-th); --output, --spp-map,\n"
    "                           --stats and --trace become patterns: '#'s become the frame\n"
    "                           number zero-padded (-o turn_####.png), else the number (4\n"
    "                           digits) goes before the extension\n"
    "      --frame <N>          Render frame N alone (the same bytes as in a range)\n"
    "      --turntable <DEGREES:FRAMES>\n"
    "                           Orbit the camera about its lookat by DEGREES every FRAMES\n"
    "                           frames (frame f at f x DEGREES / FRAMES)\n"
    "                           With --resume, frames whose files exist are skipped\n";

static const char checkpoint[] =
    "Checkpoint:\n"
    "      --checkpoint <FILE>  Checkpoint of the samples done so far [default: OUTPUT.ckpt]\n"
    "      --checkpoint-interval <SECONDS>\n"
    "                           Time between checkpoint writes (0: whenever rows\n"
    "                           complete) [default: 60]\n"
    "      --resume             Continue from the checkpoint (refused if it is from\n"
    "                           another job)\n"
    "      --keep-checkpoint    Keep the checkpoint after a successful run\n"
    "      --no-checkpoint      Write no checkpoint\n";

static const char diagnostics[] =
    "Diagnostics:\n"
    "      --stats <FILE.json>  Machine-readable run summary: inputs, times per rank,\n"
    "                           version, command line, host, MPI library\n"
    "      --trace <FILE.json>  Timeline of every work unit (Chrome trace format, Perfetto)\n"
    "      --done-file <FILE>   Once the image is written, a line in FILE: 'done', the image\n"
    "                           hash, the ranks lost (for job scripts: a launcher may report\n"
    "                           a job that lost ranks as failed)\n"
    "      --version            Print the version and the build's features, then exit\n"
    "  -h, --help               Print this help\n";

static const char developer[] =
    "Developer and benchmark options:\n"
    "      --accel <NAME>       Intersector: bvh, brute (every sphere per ray), embree\n"
    "                           (only in builds with -DRT_EMBREE=ON), bvh-sse (the BVH\n"
    "                           with the SSE2 box test that x86-64 CPUs without AVX run)\n"
    "                           or bvh-scalar (the portable box test of non-x86 nodes)\n"
    "                           [default: bvh, or RT_ACCEL]\n"
    "      --prefetch <N>       Work units a rank keeps in flight [default: " RT_POLICY_STR(RT_POLICY_PREFETCH) "]\n"
    "      --serve-only         Rank 0 only hands out work (with several ranks)\n"
    "      --empty-units        Benchmark the farm: hand out and gather units without\n"
    "                           rendering them (the image is black)\n";

static const char examples[] =
    "Examples:\n"
    "  rt-mpi --width 400 -s 32 -o quick.png\n"
    "                           A quick look at the book's final scene\n"
    "  mpirun -np 4 --bind-to none rt-mpi -j 2 -o final.png\n"
    "                           4 ranks of 2 threads each; after Ctrl-C the same\n"
    "                           command with --resume continues\n"
    "  rt-mpi scene.json -o scene.exr --stats run.json\n"
    "                           A scene file (examples: share/rt-mpi/scenes), in linear\n"
    "                           float, and a JSON summary of the run\n";

static const char environment[] =
    "Environment:\n"
    "  OMP_NUM_THREADS          Threads per rank when -j is 0\n"
    "  RT_BIND                  0: never bind threads to CPUs (by default threads that\n"
    "                           exactly fill a rank's CPUs are bound one to each)\n"
    "  RT_ACCEL                 This node's default for --accel: bvh, bvh-sse or\n"
    "                           bvh-scalar (all give the same image)\n"
    "  RT_MPI_INIT              1: initialise MPI although no known launcher started the\n"
    "                           process; 0: never (default: only under mpirun, srun...)\n"
    "  OMPI_*                   Open MPI's settings, e.g. OMPI_MCA_pml=ob1 for a quicker\n"
    "                           start; as root mpirun wants OMPI_ALLOW_RUN_AS_ROOT=1 and\n"
    "                           OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1\n";

static const char *const sections[] = {intro,       output,   scene,    sampling,    parallel,
                                       frames,      checkpoint,  diagnostics, developer, examples, environment};

/* The items' text starts at this column; a line break in an exit code's
 * text goes on there. */
#define ITEM_COLUMN 27

static const struct {
    int code;
    const char *text;
} exit_codes[] = {
#define RT_EXIT_ROW(name, value, text) {value, text},
    RT_EXIT_CODES(RT_EXIT_ROW)
#undef RT_EXIT_ROW
};

/* "Exit status:" from the exit-code table, after the other sections. */
static void exit_status(char *buf, size_t n)
{
    size_t len = (size_t)snprintf(buf, n, "\nExit status:\n");
    for (size_t i = 0; i < sizeof exit_codes / sizeof exit_codes[0] && len < n; i++) {
        len += (size_t)snprintf(buf + len, n - len, "  %-*d", ITEM_COLUMN - 2, exit_codes[i].code);
        for (const char *t = exit_codes[i].text; len < n; t++) {
            size_t k = strcspn(t, "\n");
            len += (size_t)snprintf(buf + len, n - len, "%.*s\n", (int)k, t);
            if (!t[k])
                break;
            t += k;
            len += len < n ? (size_t)snprintf(buf + len, n - len, "%*s", ITEM_COLUMN, "") : 0;
        }
    }
}

const char *rt_cli_usage(void)
{
    static char text[16384]; /* the help is 7.5 kB */
    if (!text[0]) {
        size_t len = 0;
        for (size_t i = 0; i < sizeof sections / sizeof sections[0]; i++)
            len += (size_t)snprintf(text + len, sizeof text - len, "%s%s", i ? "\n" : "", sections[i]);
        exit_status(text + len, sizeof text - len);
    }
    return text;
}
