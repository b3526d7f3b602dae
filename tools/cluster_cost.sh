#!/bin/bash
# cluster_cost.sh [BUILD_DIR] [REPEATS] - what running across hosts costs
# against one host, on the test cluster of tests/cluster/cluster.sh (root).
#
# The same 3-rank job twice: all three ranks on n1 (shared memory), and one
# rank on each of n1, n2, n3 (TCP over the cluster's veth/bridge). Both are
# started by mpirun on n1 with the same launch agent, so the difference is
# the remote daemons' start-up and the network. Jobs:
#   tiny     160x100, 1 spp   (start-up, scene broadcast, little else)
#   empty    640x400, 64 spp --empty-units (the farm's own traffic: units
#            handed out and results gathered, nothing rendered)
#   normal   320x200, 32 spp  (a render that does some work)
# Printed per job and placement (median of REPEATS runs, default 3):
# mpirun's wall time, rt-mpi's own total and render time, the sum over ranks
# of the seconds waiting for work and in MPI calls (--stats), and the bytes
# that crossed n2's cable. Both placements share the machine's 2 cores.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=$(readlink -f "${1:-$ROOT/build}")
REPEATS=${2:-3}
BIN=$BUILD/rt-mpi
[[ -x $BIN ]] || { echo "cluster_cost.sh: no $BIN (build first)" >&2; exit 2; }
source "$ROOT/scripts/mpi_env.sh"
source "$ROOT/tests/cluster/cluster.sh"
WORK=$(mktemp -d /tmp/rt-cluster-cost.XXXXXX)
trap 'cluster_down; rm -rf "$WORK"' EXIT
cluster_up 3 2>/dev/null || { echo "cluster_cost.sh: cannot make the test cluster (root? iproute2?)" >&2; exit 2; }
NET=$(cut -d. -f1-3 <"$RT_CLUSTER/hosts/n1.addr").0/24
printf 'n1 slots=3\n' >"$WORK/one"
printf 'n1 slots=1\nn2 slots=1\nn3 slots=1\n' >"$WORK/three"

eth_bytes() { cluster_exec "$1" cat /proc/net/dev | awk '$1 == "eth0:" {print $2 + $10}'; }
# one run: prints "mpirun_s total_s render_s wait_sum comm_sum bytes_n2"
run() { # hostfile args...
    local hf=$1 t0 t1 b0 b1
    shift
    rm -f "$WORK/out.png" "$WORK/stats.json"
    b0=$(eth_bytes n2)
    t0=$(date +%s.%N)
    cluster_exec n1 mpirun --hostfile "$hf" --mca plm_rsh_agent "$RT_CLUSTER/agent" --mca btl self,vader,tcp \
        --mca btl_tcp_if_include "$NET" --mca oob_tcp_if_include "$NET" --bind-to none -np 3 \
        "$BIN" -q -j 1 --no-checkpoint -o "$WORK/out.png" --stats "$WORK/stats.json" "$@" >"$WORK/run.out"
    t1=$(date +%s.%N)
    b1=$(eth_bytes n2)
    python3 - "$WORK/stats.json" "$t0" "$t1" "$((b1 - b0))" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
wait = sum(r["wait_seconds"] for r in s["per_rank"])
comm = sum(r["comm_seconds"] for r in s["per_rank"])
print(f'{float(sys.argv[3]) - float(sys.argv[2]):.3f} {s["total_seconds"]:.3f} {s["render_seconds"]:.3f} '
      f'{wait:.3f} {comm:.3f} {sys.argv[4]} {s["image_hash"]}')
EOF
}
median() { sort -n | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }

echo "| job | placement | mpirun wall s | rt-mpi total s | render s | wait s (sum) | comm s (sum) | bytes via n2's eth0 | image hash |"
echo "|---|---|---|---|---|---|---|---|---|"
for job in tiny empty normal; do
    case $job in
        tiny) args=(--width 160 --height 100 -s 1) ;;
        empty) args=(--width 640 --height 400 -s 64 --empty-units) ;;
        normal) args=(--width 320 --height 200 -s 32) ;;
    esac
    for place in one three; do
        : >"$WORK/rows"
        for ((i = 0; i < REPEATS; i++)); do run "$WORK/$place" "${args[@]}" >>"$WORK/rows"; done
        cols=()
        for c in 1 2 3 4 5 6; do cols+=("$(cut -d' ' -f$c "$WORK/rows" | median)"); done
        hashes=$(cut -d' ' -f7 "$WORK/rows" | sort -u | tr '\n' ' ')
        label=$([[ $place == one ]] && echo "3 ranks on n1" || echo "1 rank on each of n1 n2 n3")
        echo "| $job ${args[*]} | $label | ${cols[0]} | ${cols[1]} | ${cols[2]} | ${cols[3]} | ${cols[4]} | ${cols[5]} | $hashes|"
    done
done
