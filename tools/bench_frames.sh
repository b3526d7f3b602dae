#!/bin/bash
# bench_frames.sh [--bin PATH] [--np N] [--frames F] [--width W] [--height H] [--spp S] [--scene NAME]
# A frame sequence as one job against one run per frame, measured in this
# one run: F frames (default 48) of a W x H (default 320 x 180) turntable
# (--turntable 360:F) of the scene (default final) at S spp (default 64) on
# mpirun -np N (default 2): first `--frames 0-(F-1)` in one job, then F runs
# of `--frame f`. Prints each side's wall time, its time per frame, the
# ratio, and the per-frame overhead of separate runs (their extra time per
# frame) - and checks that both sides wrote the same bytes.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BIN=$ROOT/build/rt-mpi NP=2 F=48 WIDTH=320 HEIGHT=180 SPP=64 SCENE=final
while [ $# -gt 0 ]; do
    case $1 in
    --bin) BIN=$2; shift ;;
    --np) NP=$2; shift ;;
    --frames) F=$2; shift ;;
    --width) WIDTH=$2; shift ;;
    --height) HEIGHT=$2; shift ;;
    --spp) SPP=$2; shift ;;
    --scene) SCENE=$2; shift ;;
    *) echo "bench_frames.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
source "$ROOT/scripts/mpi_env.sh"
MPIRUN=${MPIRUN:-mpirun}
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT
ARGS=(--scene "$SCENE" --width "$WIDTH" --height "$HEIGHT" -s "$SPP" --turntable "360:$F" -q --no-checkpoint)
run() { "$MPIRUN" -np "$NP" --oversubscribe --bind-to none "$BIN" "${ARGS[@]}" "$@" >/dev/null; }
now() { date +%s.%N; }

t0=$(now)
run --frames "0-$((F - 1))" -o "$W/job_###.png"
t1=$(now)
for ((f = 0; f < F; f++)); do run --frame "$f" -o "$W/one_###.png"; done
t2=$(now)

same=0
for ((f = 0; f < F; f++)); do
    n=$(printf "%03d" "$f")
    cmp -s "$W/job_$n.png" "$W/one_$n.png" && same=$((same + 1))
done
echo "load average at the end: $(cut -d' ' -f1-3 /proc/loadavg); $(nproc) CPUs"
echo "$F frames, $SCENE $WIDTH x $HEIGHT, $SPP spp, --turntable 360:$F, mpirun -np $NP"
awk -v a="$t0" -v b="$t1" -v c="$t2" -v f="$F" -v same="$same" 'BEGIN {
    job = b - a; sep = c - b
    printf "one job (--frames 0-%d):   %8.2f s, %.3f s per frame\n", f - 1, job, job / f
    printf "%d runs (--frame N each): %8.2f s, %.3f s per frame\n", f, sep, sep / f
    printf "separate runs / one job:   %8.2fx; overhead of a separate run: %.3f s per frame\n", sep / job, (sep - job) / f
    printf "frames byte-identical on both sides: %d of %d\n", same, f
}'
[ "$same" -eq "$F" ]
