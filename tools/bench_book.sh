#!/bin/bash
# bench_book.sh --book DIR [--scene NAME] [--width W] [--spp S] [--depth D]
#               [--rounds N] [--compare] [--same-instance] [--rt-opts "..."]
# rt-mpi against the book series' own program on one of book 2's scenes, at
# the same size, samples and depth, one core each, measured in this one run:
#   - speed: paths per second of each whole process (width x height x spp
#     over wall time), the median of --rounds interleaved runs (default 3),
#     and the ratio;
#   - with --compare: the images as the viewer sees them (8-bit, gamma 2,
#     which both programs write): channel means, and the block-8 RMSE of
#     ours against the book's, beside the book's against itself rendered
#     with another random stream (tools/compare_images.py);
#   - with --same-instance (book2-final; implies --compare): the book's
#     program also prints its random instance (the ground boxes' heights
#     and the 1000 spheres' centres, drawn from its rand() interleaved with
#     its BVH's and Perlin tables' draws), which becomes one of our version-2
#     scene files (instance.json), and rt-mpi renders that file instead of
#     its own seeded instance: both images show the same boxes and spheres.
#     The book's second render keeps the instance (srand(1) for the scene)
#     and reseeds rand() before rendering (BOOK_RENDER_SEED=2).
# DIR is a checkout of the book's programs (RayTracing/raytracing.github.io,
# v4.0.0-alpha.1: its src/TheNextWeek and src/external, and images/ or the
# directory itself holding earthmap.jpg). The program is built unchanged but
# for the size, samples and depth, and for `srand(BOOK_SEED)` at the start of
# main (its random numbers come from rand(); seed 1 is its own default), in
# $BENCH_BOOK_DIR (default build-bench-book/). Both sides trace brute-force
# paths: rt-mpi runs --no-roulette --no-light-sampling (the book has no
# roulette and samples no lights).
# Scene names and the book's numbers: bouncing-spheres 1, checkered-spheres
# 2, earth 3, perlin-spheres 4, quads 5, simple-light 6, cornell-box 7,
# cornell-smoke 8, book2-final 9.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$ROOT/tools/bench_lib.sh"
DIR=${BENCH_BOOK_DIR:-$ROOT/build-bench-book}
BOOK="" SCENE=cornell-box W=200 SPP=16 DEPTH=40 ROUNDS=3 COMPARE=0 SAME=0 RTOPTS=""
while [ $# -gt 0 ]; do
    case $1 in
    --book) BOOK=$2; shift ;;
    --scene) SCENE=$2; shift ;;
    --width) W=$2; shift ;;
    --spp) SPP=$2; shift ;;
    --depth) DEPTH=$2; shift ;;
    --rounds) ROUNDS=$2; shift ;;
    --compare) COMPARE=1 ;;
    --same-instance) SAME=1 COMPARE=1 ;;
    --rt-opts) RTOPTS=$2; shift ;;
    *) echo "bench_book.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
[ -n "$BOOK" ] && [ -d "$BOOK/src/TheNextWeek" ] ||
    { echo "bench_book.sh: --book DIR must hold the book's src/TheNextWeek" >&2; exit 2; }
for v in "$W" "$SPP" "$DEPTH" "$ROUNDS"; do
    [[ $v =~ ^[1-9][0-9]*$ ]] || { echo "bench_book.sh: sizes and counts must be positive numbers" >&2; exit 2; }
done
case $SCENE in
bouncing-spheres) NUM=1 ASPECT=16/9 ;; checkered-spheres) NUM=2 ASPECT=16/9 ;; earth) NUM=3 ASPECT=16/9 ;;
perlin-spheres) NUM=4 ASPECT=16/9 ;; quads) NUM=5 ASPECT=1 ;; simple-light) NUM=6 ASPECT=16/9 ;;
cornell-box) NUM=7 ASPECT=1 ;; cornell-smoke) NUM=8 ASPECT=1 ;; book2-final) NUM=9 ASPECT=1 ;;
*) echo "bench_book.sh: unknown scene '$SCENE'" >&2; exit 2 ;;
esac
# The book's height: int(width / aspect), at least 1.
H=$(awk -v w="$W" -v a="$ASPECT" 'BEGIN {split(a, f, "/"); h = int(w / (f[1] / (f[2] ? f[2] : 1))); print h < 1 ? 1 : h}')
EARTH_DIR=$BOOK
[ -f "$BOOK/images/earthmap.jpg" ] && EARTH_DIR=$BOOK/images
EARTH_DIR=$(cd "$EARTH_DIR" && pwd)
[ "$SAME" = 0 ] || [ "$SCENE" = book2-final ] ||
    { echo "bench_book.sh: --same-instance is for book2-final (the other scenes have no random instance)" >&2; exit 2; }

# The book's program for this scene and size, built once.
SUFFIX="" INSTANCE=""
[ "$SAME" = 0 ] || SUFFIX=-inst INSTANCE=", the book's instance"
PROG=$DIR/book-$NUM-$W-$SPP-$DEPTH$SUFFIX/prog
if [ ! -x "$PROG" ]; then
    B=$(dirname "$PROG")
    rm -rf "$B" && mkdir -p "$B"
    cp -r "$BOOK/src/TheNextWeek" "$BOOK/src/external" "$B/" && chmod -R u+w "$B"
    cam=$B/TheNextWeek/camera.h main=$B/TheNextWeek/main.cc
    grep -q '    void initialize() {' "$cam" && grep -q 'switch (0)' "$main" && grep -q '^int main() {' "$main" ||
        { echo "bench_book.sh: $BOOK is not the book version this script knows (v4.0.0-alpha.1)" >&2; exit 2; }
    sed -i "s|^    void initialize() {|&\n        image_width = $W; samples_per_pixel = $SPP; max_depth = $DEPTH;|" "$cam"
    sed -i "s/switch (0)/switch ($NUM)/; s|^int main() {|&\n    { const char *e = getenv(\"BOOK_SEED\"); srand(e ? atoi(e) : 1); }|" "$main"
    sed -i '1i #include <cstdlib>' "$main"
    if [ "$SAME" = 1 ]; then # print the instance on stderr as it is drawn
        grep -q '^            boxes1.add(box(point3(x0,y0,z0), point3(x1,y1,z1), ground));' "$main" &&
            grep -q '^        boxes2.add(make_shared<sphere>(point3::random(0,165), 10, white));' "$main" ||
            { echo "bench_book.sh: final_scene is not as this script knows it" >&2; exit 2; }
        sed -i -e 's|^            boxes1.add(box(point3(x0,y0,z0), point3(x1,y1,z1), ground));|            std::fprintf(stderr, "BOX %.17g %.17g %.17g %.17g %.17g %.17g\\n", x0, y0, z0, x1, y1, z1);\n&|' \
            -e 's|^        boxes2.add(make_shared<sphere>(point3::random(0,165), 10, white));|        { auto p = point3::random(0,165); std::fprintf(stderr, "SPH %.17g %.17g %.17g\\n", p.x(), p.y(), p.z()); boxes2.add(make_shared<sphere>(p, 10, white)); }|' \
            -e 's|^    camera cam;|    { const char *e = getenv("BOOK_RENDER_SEED"); if (e) srand(atoi(e)); }\n&|' \
            -e '1i #include <cstdio>' "$main"
    fi
    g++ -O3 -march=x86-64 -I"$B" -o "$PROG" "$main" 2>"$B/build.log" ||
        { tail -5 "$B/build.log" >&2; echo "bench_book.sh: the book's program did not build" >&2; exit 2; }
fi
BIN=$(RT_BUILD_TARGET=rt-mpi "$ROOT/scripts/setup.sh" "$ROOT/build") # builds (or brings up to date)
OUT=$DIR/run-$SCENE-$W-$SPP-$DEPTH
mkdir -p "$OUT"

# wall SECONDS-FILE command...: runs it, stores its wall time in seconds.
wall() {
    local f=$1 t0 t1
    shift
    t0=$(date +%s.%N)
    "$@"
    t1=$(date +%s.%N)
    awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.3f\n", b - a}' >>"$f"
}
# The book's instance (BOX and SPH lines) as our scene file: book 2's final
# scene as its main.cc builds it, with these boxes and spheres.
instance_json() { # book's stderr
    awk -v earth="$EARTH_DIR/earthmap.jpg" '
    /^BOX / { box[nb++] = sprintf("{\"min\": [%s, %s, %s], \"max\": [%s, %s, %s], \"material\": \"ground\"}", $2, $3, $4, $5, $6, $7) }
    /^SPH / { sph[ns++] = sprintf("{\"center\": [%s, %s, %s], \"radius\": 10, \"material\": \"white\"}", $2, $3, $4) }
    function list(a, n,   i, t) { for (i = 0; i < n; i++) t = t (i ? ",\n    " : "\n    ") a[i]; return t }
    END {
        if (nb != 400 || ns != 1000) { print "bench_book.sh: the book printed " nb " boxes, " ns " spheres" > "/dev/stderr"; exit 1 }
        print "{\"version\": 2,"
        print " \"camera\": {\"lookfrom\": [478, 278, -600], \"lookat\": [278, 278, 0], \"vfov\": 40, \"pixels\": \"book2\"},"
        print " \"background\": {\"color\": [0, 0, 0]},"
        print " \"textures\": [{\"name\": \"earth\", \"type\": \"image\", \"path\": \"" earth "\"}, {\"name\": \"marble\", \"type\": \"marble\", \"scale\": 0.1}],"
        print " \"materials\": [{\"name\": \"ground\", \"type\": \"lambertian\", \"albedo\": [0.48, 0.83, 0.53]},"
        print "  {\"name\": \"light\", \"type\": \"emitter\", \"emit\": [7, 7, 7], \"two_sided\": true},"
        print "  {\"name\": \"glass\", \"type\": \"dielectric\", \"ior\": 1.5},"
        print "  {\"name\": \"white\", \"type\": \"lambertian\", \"albedo\": [0.73, 0.73, 0.73]}],"
        print " \"boxes\": [" list(box, nb) "],"
        print " \"quads\": [{\"q\": [123, 554, 147], \"u\": [300, 0, 0], \"v\": [0, 0, 265], \"material\": \"light\"}],"
        print " \"moving_spheres\": [{\"center0\": [400, 400, 200], \"center1\": [430, 400, 200], \"radius\": 50,"
        print "   \"material\": {\"type\": \"lambertian\", \"albedo\": [0.7, 0.3, 0.1]}}],"
        print " \"spheres\": [{\"center\": [260, 150, 45], \"radius\": 50, \"material\": \"glass\"},"
        print "  {\"center\": [0, 150, 145], \"radius\": 50, \"material\": {\"type\": \"metal\", \"albedo\": [0.8, 0.8, 0.9], \"fuzz\": 1}},"
        print "  {\"center\": [360, 150, 145], \"radius\": 70, \"material\": \"glass\"},"
        print "  {\"center\": [400, 200, 400], \"radius\": 100, \"material\": {\"type\": \"lambertian\", \"texture\": \"earth\"}},"
        print "  {\"center\": [220, 280, 300], \"radius\": 80, \"material\": {\"type\": \"lambertian\", \"texture\": \"marble\"}}],"
        print " \"media\": [{\"sphere\": {\"center\": [360, 150, 145], \"radius\": 70}, \"density\": 0.2,"
        print "   \"material\": {\"type\": \"isotropic\", \"albedo\": [0.2, 0.4, 0.9]}},"
        print "  {\"sphere\": {\"center\": [0, 0, 0], \"radius\": 5000}, \"density\": 0.0001,"
        print "   \"material\": {\"type\": \"isotropic\", \"albedo\": [1, 1, 1]}}],"
        print " \"instances\": [{\"objects\": {\"spheres\": [" list(sph, ns) "]},"
        print "   \"rotate_y\": 15, \"translate\": [-100, 270, 395]}]}"
    }' "$1"
}
WHAT=(--scene "$SCENE" --texture-dir "$EARTH_DIR")
[ "$SAME" = 0 ] || WHAT=(--scene-file "$OUT/instance.json")
rm -f "$OUT"/*.sec
for ((r = 1; r <= ROUNDS; r++)); do
    (cd "$OUT" && RTW_IMAGES=$EARTH_DIR BOOK_SEED=1 wall "$OUT/book.sec" "$PROG" >"$OUT/book1.ppm" 2>"$OUT/book1.err")
    if [ "$SAME" = 1 ] && [ "$r" = 1 ]; then
        instance_json "$OUT/book1.err" >"$OUT/instance.json"
    fi
    # shellcheck disable=SC2086 # RTOPTS is a list of options
    wall "$OUT/ours.sec" "$BIN" "${WHAT[@]}" --width "$W" --height "$H" -s "$SPP" \
        --max-depth "$DEPTH" --no-roulette --no-light-sampling -j 1 -q $RTOPTS -o "$OUT/ours.png" >"$OUT/ours.txt"
done
tb=$(median <"$OUT/book.sec") to=$(median <"$OUT/ours.sec")
paths=$((W * H * SPP))
echo "scene $SCENE (book 2 scene $NUM)$INSTANCE, ${W}x${H}, $SPP spp, depth $DEPTH, one core each, median of $ROUNDS"
printf '  book program: %8.3f s  %10.0f paths/s\n' "$tb" "$(awk -v p=$paths -v t="$tb" 'BEGIN {print p / t}')"
printf '  rt-mpi -j 1:  %8.3f s  %10.0f paths/s\n' "$to" "$(awk -v p=$paths -v t="$to" 'BEGIN {print p / t}')"
echo "  rt-mpi / book (paths per second): $(ratio "$tb" "$to")"
if [ "$COMPARE" = 1 ]; then
    # with the same instance: the same scene (seed 1), then another stream
    RENDER=(BOOK_SEED=2)
    [ "$SAME" = 0 ] || RENDER=(BOOK_SEED=1 BOOK_RENDER_SEED=2)
    (cd "$OUT" && env RTW_IMAGES="$EARTH_DIR" "${RENDER[@]}" "$PROG" >"$OUT/book2.ppm" 2>"$OUT/book2.err")
    [ "$SAME" = 0 ] || cmp -s <(grep -E '^(BOX|SPH) ' "$OUT/book1.err") <(grep -E '^(BOX|SPH) ' "$OUT/book2.err") ||
        { echo "bench_book.sh: the book's second render drew another instance" >&2; exit 1; }
    /usr/bin/python3 "$ROOT/tools/compare_images.py" --ref "$OUT/book1.ppm" \
        "rt-mpi=$OUT/ours.png" "book, other stream=$OUT/book2.ppm"
fi
