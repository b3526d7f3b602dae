#!/bin/bash
# handout.sh - runs bench_handout over its schemes at -np 2, 4 and 8 and
# prints the table of docs/notes/handout.md (issue 26, point 2).
#
#   tools/bench/handout.sh [--bin build/bench_handout] [--out FILE.jsonl]
#                          [--np "2 4 8"] [--reps 3] [--seconds 1]
#
# Each configuration first runs once to find how many units make about
# --seconds of wall time (at least 2000 a chunk), then --reps times with
# that count, the configurations taken in turn on each round (alternating).
# Before every run it waits until no rt-mpi, validate_scaling or ctest
# runs on the machine. Each run's JSON line goes to --out; the table
# (medians) goes to stdout (tools/bench/handout_table.py).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
bin=$root/build/bench_handout
out=handout.jsonl
nps="2 4 8"
reps=3
secs=1
while [ $# -gt 0 ]; do
    case $1 in
    --bin) bin=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --np) nps=$2; shift 2 ;;
    --reps) reps=$2; shift 2 ;;
    --seconds) secs=$2; shift 2 ;;
    *) echo "handout.sh: unknown option $1" >&2; exit 2 ;;
    esac
done
# shellcheck source=/dev/null
source "$root/scripts/mpi_env.sh"

quiet() { while pgrep -f 'rt-mpi|validate_scaling|ctest' >/dev/null; do sleep 15; done; }

# name | mpirun options | bench options
configs=()
for pc in "1 1" "2 1" "4 1" "8 4" "32 16"; do
    # shellcheck disable=SC2086
    set -- $pc
    configs+=("p2p|  |--scheme p2p --prefetch $1 --chunk $2")
done
for osc in rdma pt2pt ucx; do
    for c in 1 4 16; do
        for mode in "poll 1" "poll 0" "block 1" "block 0"; do
            # shellcheck disable=SC2086
            set -- $mode
            configs+=("rma|--mca osc $osc|--scheme rma --chunk $c --root $1 --reports $2")
        done
    done
done

run() { # np mpirun-options bench-options units
    quiet
    # shellcheck disable=SC2086
    timeout 300 mpirun -np "$1" --oversubscribe --bind-to none $2 "$bin" $3 --units "$4"
}

declare -A units
: >"$out"
for np in $nps; do
    for k in "${!configs[@]}"; do
        IFS='|' read -r _ mo bo <<<"${configs[$k]}"
        c=$(sed -n 's/.*--chunk \([0-9]*\).*/\1/p' <<<"$bo")
        line=$(run "$np" "$mo" "$bo" $((2000 * c)))
        units[$np.$k]=$(python3 -c "import json,sys; d=json.loads(sys.argv[1]); c=$c; \
n=int(d['units_per_s']*$secs); n=max(2000*c, min(n, 4000000)); print(n//c*c)" "$line")
    done
done
for ((r = 1; r <= reps; r++)); do
    for np in $nps; do
        for k in "${!configs[@]}"; do
            IFS='|' read -r _ mo bo <<<"${configs[$k]}"
            run "$np" "$mo" "$bo" "${units[$np.$k]}" >>"$out"
        done
    done
done
python3 "$here/handout_table.py" "$out"
