#!/bin/bash
# bench_lights.sh [--bin PATH] [--size N] [--ref-spp S] [--scenes "A B"] [--texture-dir DIR]
#                 [--book DIR] [--book-spp S] [--book-size N] [--rounds R]
# Light sampling (next-event estimation with MIS, rt-mpi's defaults:
# Russian roulette on) against brute-force paths (--no-light-sampling, the
# same defaults otherwise), measured in this one run, every render on one
# core (-j 1): for each scene (default cornell-box and book2-final, N x N,
# default 128), a reference rendered with light sampling at --ref-spp
# (default 4096, -j 2); the brute-force render at 1024 spp and its
# display-space RMSE (gamma 2, 0-255, per pixel: tools/compare_images.py
# --block 1) against the reference; light sampling at 1, 2, 4, ... spp
# until its RMSE is at most the brute-force one. Then --rounds rounds
# (default 3) time the brute-force render and the last two light-sampled
# ones, interleaved (A B B', A B B', ...) so a drift of the machine's load
# hits both sides; the medians are kept (the images, so the RMSEs, are the
# same every time). The time to the brute force's RMSE is interpolated (log
# time against log RMSE) between the two light-sampled renders. Times are
# CPU seconds (user + system) of the whole process, and wall seconds; the
# load average is printed before and after. book2-final reads earthmap.jpg
# from --texture-dir (default: the current directory).
# With --book DIR (the book's programs: DIR/run.sh), book3-final N x N
# (--book-size, default 256) against the book's own light-sampling program
# (`run.sh rest`, one core, --book-spp samples, default 64) the same way:
# the book's side timed against ours at the two sample counts that bracket
# its RMSE.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$ROOT/tools/bench_lib.sh"
BIN=$ROOT/build/rt-mpi SIZE=128 REF=4096 SCENES="cornell-box book2-final" BOOK="" BOOK_SPP=64 BOOK_SIZE=256
TEX=. ROUNDS=3
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
    --rounds) ROUNDS=$2; shift ;;
    *) echo "bench_lights.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT
load() { echo "# load average: $(cut -d' ' -f1-3 /proc/loadavg)"; }

# timed OUT CMD...: runs CMD with its standard output to OUT; prints
# "cpu wall" (seconds: user + system, and elapsed).
timed() {
    local out=$1 t
    shift
    t=$( { TIMEFORMAT='%U %S %R'; time "$@" >"$out" 2>"$W/err"; } 2>&1) ||
        { echo "bench_lights.sh: $*: $(head -c 300 "$W/err")" >&2; exit 1; }
    awk '{printf "%.3f %.3f", $1 + $2, $3}' <<<"$t"
}
# ours OUT ARGS...: rt-mpi renders SIZE x SIZE to OUT; prints "cpu wall".
ours() {
    local out=$1
    shift
    timed /dev/null "$BIN" --width "$SIZE" --height "$SIZE" --texture-dir "$TEX" -q -o "$out" "$@"
}
le() { awk -v a="$1" -v b="$2" 'BEGIN {exit !(a <= b)}'; }
# reach E0 T0 E1 T1 E: the time at which the error reaches E, between
# (E0, T0) and (E1, T1), E1 <= E < E0 (log-log; T1 when there is no E0).
reach() {
    awk -v e0="$1" -v t0="$2" -v e1="$3" -v t1="$4" -v e="$5" 'BEGIN {
        if (e0 == "" || e0 <= e1) { printf "%.3f", t1; exit }
        f = log(e0 / e) / log(e0 / e1); printf "%.3f", exp(log(t0) + f * (log(t1) - log(t0))) }'
}
# bracket EREF ARGS...: the light-sampled renders at 1, 2, 4, ... spp until
# the RMSE is at most EREF; prints "spp0 rmse0 spp1 rmse1" of the last two
# (spp0 and rmse0 "-" when the first already reaches it).
bracket() {
    local eref=$1 spp=1 s0=- e0=- el
    shift
    while :; do
        ours "$W/l.png" -s $spp "$@" >/dev/null
        el=$(display_rmse "$W/ref.png" "$W/l.png")
        if le "$el" "$eref" || [ $spp -ge 4096 ]; then
            echo "$s0 $e0 $spp $el"
            return
        fi
        s0=$spp e0=$el spp=$((spp * 2))
    done
}
# compare LABEL EREF "OTHER-CMD" ARGS...: ROUNDS rounds of the other side
# (OTHER-CMD, evaluated) and ours at the two sample counts that bracket
# EREF; prints one table row: both sides' median times and the ratios.
compare() {
    local label=$1 eref=$2 other=$3 s0 e0 s1 e1 i
    shift 3
    read -r s0 e0 s1 e1 < <(bracket "$eref" "$@")
    : >"$W/t.b" && : >"$W/t.0" && : >"$W/t.1"
    for ((i = 0; i < ROUNDS; i++)); do
        eval "$other" >>"$W/t.b"
        echo >>"$W/t.b"
        [ "$s0" = - ] || { ours "$W/l.png" -s "$s0" "$@" >>"$W/t.0"; echo >>"$W/t.0"; }
        ours "$W/l.png" -s "$s1" "$@" >>"$W/t.1"
        echo >>"$W/t.1"
    done
    col() { cut -d' ' -f"$2" "$W/$1" | median; }
    local cb wb c0=- w0=- c1 w1 ci wi
    cb=$(col t.b 1) wb=$(col t.b 2) c1=$(col t.1 1) w1=$(col t.1 2)
    [ "$s0" = - ] || { c0=$(col t.0 1) w0=$(col t.0 2); }
    [ "$s0" = - ] && e0=""
    ci=$(reach "$e0" "$c0" "$e1" "$c1" "$eref") wi=$(reach "$e0" "$w0" "$e1" "$w1" "$eref")
    printf "%-14s | RMSE %s: %s s cpu (%s s wall) | %s spp: RMSE %s, %s spp: RMSE %s; at %s: %s s cpu (%s s wall) | %sx cpu, %sx wall\n" \
        "$label" "$eref" "$cb" "$wb" "$s0" "${e0:--}" "$s1" "$e1" "$eref" "$ci" "$wi" \
        "$(awk -v a="$cb" -v b="$ci" 'BEGIN {printf "%.1f", a / b}')" \
        "$(awk -v a="$wb" -v b="$wi" 'BEGIN {printf "%.1f", a / b}')"
}

load
if [ -n "$SCENES" ]; then
    echo "# $SIZE x $SIZE, one core (-j 1); reference: light sampling, $REF spp (-j 2); RMSE: display space" \
        "(gamma 2, 0-255) against it; medians of $ROUNDS interleaved rounds"
    echo "# scene | brute force (--no-light-sampling), 1024 spp | light sampling: the two sample counts" \
        "around that RMSE, the time interpolated to it | time ratio at equal RMSE"
fi
for s in $SCENES; do
    ours "$W/ref.png" --scene "$s" -s "$REF" -j 2 >/dev/null
    ours "$W/b.png" --scene "$s" -s 1024 -j 1 --no-light-sampling >/dev/null
    compare "$s" "$(display_rmse "$W/ref.png" "$W/b.png")" \
        "ours \"\$W/b.png\" --scene $s -s 1024 -j 1 --no-light-sampling" --scene "$s" -j 1
done
load

[ -n "$BOOK" ] || exit 0
SIZE=$BOOK_SIZE
ours "$W/ref.png" --scene book3-final -s "$REF" -j 2 >/dev/null
BOOKCMD="timed \"\$W/book.ppm\" \"$BOOK/run.sh\" rest $SIZE $BOOK_SPP 50"
eval "$BOOKCMD" >/dev/null # builds on its first use
echo "# book3-final, $SIZE x $SIZE, one core each; reference: rt-mpi, $REF spp (-j 2); medians of $ROUNDS" \
    "interleaved rounds"
echo "# the book's rest, $BOOK_SPP spp | rt-mpi -j 1: the two sample counts around that RMSE, the time" \
    "interpolated to it | time ratio per core"
compare "book's rest" "$(display_rmse "$W/ref.png" "$W/book.ppm")" "$BOOKCMD" --scene book3-final -j 1
load
