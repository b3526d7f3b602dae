#!/bin/bash
# lockstep_probe.sh [--rounds N] [--bin RT_MPI]
# Issue 35's question, measured in one run: how much faster could book 2's
# Cornell box be traced by brute force if eight paths ran in the lanes of an
# AVX-512 register? Builds tools/lockstep_probe.c (a stand-alone loop over
# the same scene, not part of rt-mpi) and runs, interleaved, N rounds of
#   - rt-mpi (default build/rt-mpi): cornell-box, 200 x 200, 16 spp, depth
#     40, -j 1, --no-roulette --no-light-sampling: its render time over its
#     ray segments (--stats);
#   - the probe's four loops: scalar (one path at a time, every quad in
#     turn), lanes (eight paths a register, numbers from a hash), sobol
#     (lanes, with rt-mpi's Sobol sampler drawn lane by lane) and sobol8
#     (the same numbers computed for the eight lanes in vector code).
# Prints nanoseconds a ray segment, the least and the median of the rounds,
# and rt-mpi's over each loop's. First it checks that scalar and lanes
# trace the same segments to the bit (a build with -DPROBE_CHECK prints a
# fingerprint of every hit), and sobol and sobol8 too: exit 1 if not. Needs a CPU with AVX-512 F and
# DQ (exit 2 without).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$ROOT/tools/bench_lib.sh"
ROUNDS=5 BIN=$ROOT/build/rt-mpi
while [ $# -gt 0 ]; do
    case $1 in
    --rounds) ROUNDS=$2; shift ;;
    --bin) BIN=$2; shift ;;
    *) echo "lockstep_probe.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
[ -x "$BIN" ] || { echo "lockstep_probe.sh: no rt-mpi at $BIN (scripts/setup.sh build)" >&2; exit 2; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
for d in "" -DPROBE_CHECK; do
    cc -O2 -march=x86-64-v4 -ffp-contract=off $d -I"$ROOT/src/core" -o "$TMP/probe$d" \
        "$ROOT/tools/lockstep_probe.c" "$ROOT/src/core/sampler.c" -lm
done
# scalar and lanes trace the same segments to the bit: a lane that computed
# otherwise would change the fingerprint of the hits (without AVX-512 the
# probe prints its error and exits 2, and so does this script: pipefail)
for v in scalar lanes; do
    "$TMP/probe-DPROBE_CHECK" $v | sed -n 's/.*image hash \([0-9a-f]*\), segments. fingerprint \([0-9a-f]*\)$/\1 \2/p' >"$TMP/$v.check"
done
[ -s "$TMP/lanes.check" ] && cmp -s "$TMP/scalar.check" "$TMP/lanes.check" ||
    { echo "lockstep_probe.sh: error: lanes (image hash, fingerprint) $(cat "$TMP/lanes.check") != scalar's $(cat "$TMP/scalar.check")" >&2; exit 1; }
echo "scalar and lanes: the same segments (image hash, fingerprint: $(cat "$TMP/lanes.check"))"
for v in sobol sobol8; do
    "$TMP/probe-DPROBE_CHECK" $v | sed -n 's/.*image hash \([0-9a-f]*\), segments. fingerprint \([0-9a-f]*\)$/\1 \2/p' >"$TMP/$v.check"
done
[ -s "$TMP/sobol8.check" ] && cmp -s "$TMP/sobol.check" "$TMP/sobol8.check" ||
    { echo "lockstep_probe.sh: error: sobol8 (image hash, fingerprint) $(cat "$TMP/sobol8.check") != sobol's $(cat "$TMP/sobol.check")" >&2; exit 1; }
echo "sobol and sobol8: the same segments (image hash, fingerprint: $(cat "$TMP/sobol8.check"))"

for r in $(seq "$ROUNDS"); do
    "$BIN" --scene cornell-box --width 200 --height 200 -s 16 --max-depth 40 -j 1 --no-roulette \
        --no-light-sampling --no-checkpoint --quiet -o "$TMP/rt.png" --stats "$TMP/rt.json" >/dev/null
    /usr/bin/python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(d['render_seconds']/d['ray_segments']*1e9)" \
        "$TMP/rt.json" >>"$TMP/rt-mpi"
    for v in scalar lanes sobol sobol8; do
        "$TMP/probe" $v | sed -n 's/.*, \([0-9.]*\) ns a segment.*/\1/p' >>"$TMP/$v"
    done
done
least() { sort -g | head -1; }
printf '%-36s %10s %10s %14s\n' "cornell-box brute force, 200x200, 16 spp" "least ns" "median ns" "rt-mpi / it"
REF=$(least <"$TMP/rt-mpi")
for v in rt-mpi scalar lanes sobol sobol8; do
    L=$(least <"$TMP/$v") M=$(median <"$TMP/$v")
    printf '%-36s %10.2f %10.2f %14s\n' "$v" "$L" "$M" "$(ratio "$REF" "$L")"
done
