#!/bin/bash
# bench_lights.sh [--bin PATH] [--size N] [--ref-spp S] [--scenes "A B"] [--texture-dir DIR]
#                 [--book DIR] [--book-spp S] [--book-size N]
# Light sampling (next-event estimation with MIS) against brute-force paths
# (--no-light-sampling), measured in this one run: for each scene (default
# cornell-box and book2-final, N x N, default 100), a reference rendered with
# light sampling at --ref-spp (default 8192, -j 2); the brute-force render
# at 1024 spp (-j 2): its wall time and display-space RMSE (gamma 2, 0-255,
# per pixel: tools/compare_images.py --block 1) against the reference; then
# light sampling at 4, 8, 16, ... spp (-j 2) until its RMSE is at most the
# brute-force one: the time to that RMSE, interpolated (log time against
# log RMSE) between that render and the one before. Prints both sides and
# the ratio of the times. book2-final reads earthmap.jpg from --texture-dir
# (default: the current directory).
# With --book DIR (the book's programs: DIR/run.sh), book3-final N x N
# against the book's own light-sampling program (`run.sh rest`, one core,
# --book-spp samples, default 64; --book-size N, default 128): the book's
# time and RMSE against our reference, then ours on one core (-j 1) at 1,
# 2, 4, ... spp until its RMSE is at most the book's, interpolated as
# above: the ratio of the times is time per core.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BIN=$ROOT/build/rt-mpi SIZE=100 REF=8192 SCENES="cornell-box book2-final" BOOK="" BOOK_SPP=64 BOOK_SIZE=128 TEX=.
while [ $# -gt 0 ]; do
    case $1 in
    --bin) BIN=$2; shift ;;
    --size) SIZE=$2; shift ;;
    --ref-spp) REF=$2; shift ;;
    --scenes) SCENES=$2; shift ;;
    --texture-dir) TEX=$2; shift ;;
    --book) BOOK=$2; shift ;;
    --book-spp) BOOK_SPP=$2; shift ;;
    --book-size) BOOK_SIZE=$2; shift ;;
    *) echo "bench_lights.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
PY=/usr/bin/python3 # numpy and PIL
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT

# run OUT ARGS...: renders to OUT; prints the wall time in seconds.
run() {
    local out=$1 t0 t1
    shift
    t0=$(date +%s.%N)
    "$BIN" --width "$SIZE" --height "$SIZE" --texture-dir "$TEX" -q -o "$out" "$@" >/dev/null 2>"$W/err" ||
        { echo "bench_lights.sh: rt-mpi $*: $(head -c 300 "$W/err")" >&2; exit 1; }
    t1=$(date +%s.%N)
    awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.2f", b - a}'
}
# rmse REF IMG: display-space per-pixel RMSE of IMG against REF.
rmse() { "$PY" "$ROOT/tools/compare_images.py" --ref "$1" --block 1 x="$2" | awk '$1 == "x" {print $NF}'; }
le() { awk -v a="$1" -v b="$2" 'BEGIN {exit !(a <= b)}'; }
# reach E0 T0 E1 T1 E: the time at which the error reaches E, between
# (E0, T0) and (E1, T1), E1 <= E < E0 (log-log; T1 when there is no E0).
reach() {
    awk -v e0="$1" -v t0="$2" -v e1="$3" -v t1="$4" -v e="$5" 'BEGIN {
        if (e0 == "" || e0 <= e1) { printf "%.3f", t1; exit }
        f = log(e0 / e) / log(e0 / e1); printf "%.3f", exp(log(t0) + f * (log(t1) - log(t0))) }'
}
# search OUT EREF SPP0 ARGS...: renders with SPP0, 2 SPP0, ... spp until the
# RMSE is at most EREF; prints "spp rmse time interpolated-time".
search() {
    local out=$1 eref=$2 spp=$3 e0="" t0="" el tl
    shift 3
    while :; do
        tl=$(run "$out" -s $spp "$@")
        el=$(rmse "$W/ref.png" "$out")
        if le "$el" "$eref" || [ $spp -ge 4096 ]; then
            echo "$spp $el $tl $(reach "$e0" "$t0" "$el" "$tl" "$eref")"
            return
        fi
        e0=$el t0=$tl spp=$((spp * 2))
    done
}

if [ -n "$SCENES" ]; then
    echo "# $SIZE x $SIZE; reference: light sampling, $REF spp; RMSE: display space (gamma 2, 0-255) against it"
    printf "%-12s %-30s %-46s %s\n" scene "brute force, 1024 spp (-j 2)" \
        "light sampling (-j 2): first spp at that RMSE" "time ratio at equal RMSE"
fi
for s in $SCENES; do
    run "$W/ref.png" --scene "$s" -s "$REF" -j 2 >/dev/null
    tb=$(run "$W/b.png" --scene "$s" -s 1024 -j 2 --no-light-sampling)
    eb=$(rmse "$W/ref.png" "$W/b.png")
    read -r spp el tl ti < <(search "$W/l.png" "$eb" 4 --scene "$s" -j 2)
    printf "%-12s %-30s %-46s %s\n" "$s" "RMSE $eb in $tb s" "$spp spp: RMSE $el in $tl s (at $eb: $ti s)" \
        "$(awk -v a="$tb" -v b="$ti" 'BEGIN {printf "%.1fx", a / b}')"
done

[ -n "$BOOK" ] || exit 0
SIZE=$BOOK_SIZE
run "$W/ref.png" --scene book3-final -s "$REF" -j 2 >/dev/null
"$BOOK/run.sh" rest "$SIZE" "$BOOK_SPP" 50 >"$W/book.ppm" 2>/dev/null # builds on its first use
t0=$(date +%s.%N)
"$BOOK/run.sh" rest "$SIZE" "$BOOK_SPP" 50 >"$W/book.ppm" 2>/dev/null
t1=$(date +%s.%N)
tb=$(awk -v a="$t0" -v b="$t1" 'BEGIN {printf "%.2f", b - a}')
eb=$(rmse "$W/ref.png" "$W/book.ppm")
read -r spp el tl ti < <(search "$W/l.png" "$eb" 1 --scene book3-final -j 1)
echo "# book3-final, $SIZE x $SIZE, one core each; reference: rt-mpi, $REF spp"
printf "%-30s %-52s %s\n" "the book's rest, $BOOK_SPP spp" "rt-mpi -j 1: first spp at that RMSE" \
    "time ratio at equal RMSE"
printf "%-30s %-52s %s\n" "RMSE $eb in $tb s" "$spp spp: RMSE $el in $tl s (at $eb: $ti s)" \
    "$(awk -v a="$tb" -v b="$ti" 'BEGIN {printf "%.1fx", a / b}')"
