#!/bin/bash
# bench_farm.sh [REV] [--rounds N] [--np N]
# The farm on its own, this working tree (A) against git revision REV (B,
# default HEAD), side by side in one run, alternating A, B, A, B...:
#   serve  rank 0's service rate: --empty-units --serve-only, -np N (default
#          8, oversubscribed), one-row units of a 1200-pixel image: units
#          per second of render wall time, and, where the build reports when
#          its last sums came in (final_combine_seconds), units per second
#          until the last unit was reported (the hand-out rate; the rest of
#          the wall time is the workers' sums, one image of them, arriving)
#   split  a job with fewer rows than the ranks want (1200x16 at 512 spp,
#          -np N, --empty-units --serve-only): cut into column tiles since
#          d743106 (8 a row at -np 8), into sample ranges before (4 a row):
#          the bytes rank 0 receives (one image of sums at best). A counts
#          them (--stats rank0_bytes_in); a B from before that counter sent
#          each unit's rows (24 bytes a pixel) plus 32 bytes, counted from
#          its --trace.
# Prints the medians and A / B. Builds go to $AB_FARM_DIR (default
# build-ab-farm/), release with MPI.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
source "$ROOT/tools/bench_lib.sh"
DIR=${AB_FARM_DIR:-$ROOT/build-ab-farm}
REV=HEAD ROUNDS=3 NP=8
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then
    REV=$1
    shift
fi
while [ $# -gt 0 ]; do
    case $1 in
    --rounds) ROUNDS=$2; shift ;;
    --np) NP=$2; shift ;;
    *) echo "bench_farm.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
build_a_b bench_farm.sh "$ROOT" "$REV" "$DIR" -DBUILD_TESTING=OFF
COMMIT=$(cat "$DIR/b.commit")
source "$ROOT/scripts/mpi_env.sh"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
mpi() { timeout 600 mpirun -np "$NP" --oversubscribe --bind-to none "$@"; }
SERVE=(--empty-units --serve-only --width 1200 --height 8000 --band 1 -s 1 -j 1 -q --no-checkpoint)
SPLIT=(--empty-units --serve-only --width 1200 --height 16 -s 512 -j 1 -q --no-checkpoint)
serve_rate() { # a|b: units per second of render wall time
    mpi "$DIR/$1/rt-mpi" "${SERVE[@]}" -o "$T/s.png" --stats "$T/s.json" >/dev/null 2>"$T/err" ||
        { cat "$T/err" >&2; exit 1; }
    python3 - "$T/s.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
hand_out = s["render_seconds"] - s.get("final_combine_seconds", 0)
print(s["units"] / s["render_seconds"], s["units"] / hand_out)
PY
}
split_bytes() { # a|b: bytes into rank 0, and units
    mpi "$DIR/$1/rt-mpi" "${SPLIT[@]}" -o "$T/p.png" --stats "$T/p.json" --trace "$T/p.trace" >/dev/null 2>"$T/err" ||
        { cat "$T/err" >&2; exit 1; }
    python3 - "$T/p.json" "$T/p.trace" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
if "rank0_bytes_in" in s:
    print(s["rank0_bytes_in"], s["units"])
else:
    ev = [e for e in json.load(open(sys.argv[2]))["traceEvents"] if e.get("ph") == "X" and e["pid"] != 0]
    print(sum((e["args"]["y1"] - e["args"]["y0"]) * s["width"] * 24 + 32 for e in ev), s["units"])
PY
}
for ((r = 0; r < ROUNDS; r++)); do
    for v in a b; do
        serve_rate $v >>"$T/serve.$v"
        split_bytes $v >>"$T/split.$v"
    done
done
SA=$(cut -d' ' -f1 "$T/serve.a" | median) SB=$(cut -d' ' -f1 "$T/serve.b" | median)
HA=$(cut -d' ' -f2 "$T/serve.a" | median) HB=$(cut -d' ' -f2 "$T/serve.b" | median)
BA=$(cut -d' ' -f1 "$T/split.a" | median) BB=$(cut -d' ' -f1 "$T/split.b" | median)
UNITS=$(cut -d' ' -f2 "$T/split.a" | head -1)
IMAGE=$((1200 * 16 * 24))
echo "bench_farm.sh: -np $NP, $ROUNDS alternating rounds, median; B = $REV ($COMMIT)"
printf "  serve: units/s      A %10.0f   B %10.0f   A / B %s  (whole render)\n" "$SA" "$SB" "$(ratio "$SA" "$SB")"
printf "  serve: hand-out/s   A %10.0f   B %10.0f   A / B %s  (until the last unit is reported)\n" "$HA" "$HB" \
    "$(ratio "$HA" "$HB")"
printf "  split: bytes in     A %10.0f   B %10.0f   B / A %s  (%s units; one image of sums is %d bytes)\n" \
    "$BA" "$BB" "$(ratio "$BB" "$BA")" "$UNITS" "$IMAGE"
