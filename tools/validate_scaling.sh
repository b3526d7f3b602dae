#!/bin/bash
# validate_scaling.sh [--quick] [--rounds N] [--out DIR] [--bin RT_MPI] [--only serve|validate|predict|cluster]
# Measures what the scaling model (tools/simulate_scaling.py, farm v2 with
# column tiles: policy "tiles", 16 units per rank, 0.1 s flush interval)
# needs on this machine, checks the model against real runs, and predicts,
# in a few minutes. Without --only: serve, validate, predict (not cluster).
# The binary is build/rt-mpi, built or brought up to date by
# scripts/setup.sh, or --bin (e.g. a build of one commit while the work tree
# is being changed).
#   serve     rank 0's cost: --empty-units --serve-only -np 8 (rank 0 busy,
#             not napping between messages), 1-row units of 16, 1200 and
#             2400 pixels (4000 units), ROUNDS runs each; fits
#             rank0_serve_cpu_seconds = a * messages + b * bytes (all three
#             from --stats); then -np 2 runs of 1200-pixel units (their sums
#             all come in one final flush) give a worker's seconds per byte
#             to pack a flush, from final_combine_seconds -> OUT/serve.json
#   validate  real jobs at -np 1, 2, 4, 8 (-j 1; oversubscribed past the
#             cores, Open MPI's yield-when-idle off), VROUNDS runs each with
#             --trace/--stats; the -np 1 trace is the cost profile; side by
#             side: units and busy share per rank, rank 0's messages, bytes,
#             serve CPU and final combination. Three jobs: 600x400 at 16 spp
#             (row bands), 800x24 at 128 spp (column tiles from -np 2, policy
#             tiles) and the same with --split samples (sample ranges, the
#             farm before tiles: policy affinity)
#   predict   the render phase's set-up (setup_seconds of --stats: scene
#             broadcast to render start; the old total - render - write of
#             -np 1 is kept as an upper bound), MPI start-up (the rest of
#             mpirun -np 2's wall time outside render, set-up and writing)
#             and image writing (the PNG's open to its rename, strace), a
#             cost profile (1200x800 at 4 spp, -j 2, 3 runs, each row's
#             cheapest), then the efficiency of the render phase at 16
#             threads per rank, 64 ... 4096 ranks, for 1200x800 at 500 spp
#             and 3840x2160 at 500 and 4500 spp and at the samples that give
#             1 s of work per thread at 1024 and 4096 x 16: as built (tiles)
#             and the other policies, and with changes for affinity and
#             tiles (the v2 farm's 1 s flush and 8 units per rank, a 0.25 s
#             flush, 8 or 32 units per rank, rank 0's cost per byte / 4)
#   cluster   (root) the test cluster of tests/cluster/cluster.sh: 3 hosts
#             as network namespaces, TCP between them; MPI latency and
#             bandwidth between two hosts (tools/mpi_pingpong.c), then the
#             row-band and the tiled job at -np 4 and 8 spread over the
#             hosts (--map-by node), VROUNDS runs each, against the model
#             with that latency and bandwidth; every namespace and process
#             removed on exit (cluster_down)
# Results stay in OUT (default build/scaling): stats, traces, serve.json,
# validate.txt, validate.jsonl, overhead.json, predict-*.txt, cluster*.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
OUT=$ROOT/build/scaling ROUNDS=3 VROUNDS=3 ONLY="" QUICK=0 BIN=""
while [ $# -gt 0 ]; do
    case $1 in
    --quick) QUICK=1 ROUNDS=1 VROUNDS=1 ;;
    --rounds) ROUNDS=$2; shift ;;
    --out) OUT=$2; shift ;;
    --only) ONLY=$2; shift ;;
    --bin) BIN=$(readlink -f "$2"); shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "validate_scaling.sh: unknown option $1" >&2; exit 2 ;;
    esac
    shift
done
[ -n "$BIN" ] || BIN=$("$ROOT/scripts/setup.sh" "$ROOT/build") # builds, or brings up to date
[ -x "$BIN" ] || { echo "validate_scaling.sh: no binary $BIN" >&2; exit 2; }
PY=python3
[ -x /usr/bin/python3 ] && PY=/usr/bin/python3
SIM="$PY $ROOT/tools/simulate_scaling.py"
source "$ROOT/scripts/mpi_env.sh"
export OMPI_MCA_mpi_yield_when_idle=0
CORES=$(nproc)
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
TMP=$(mktemp -d)
cleanup() {
    # the test cluster (cluster part): every process in its namespaces by
    # PID, then the namespaces, by cluster.sh's own teardown
    if [ -n "${RT_CLUSTER:-}" ] && declare -F cluster_down >/dev/null; then cluster_down || true; fi
    rm -rf "$TMP"
}
trap cleanup EXIT
# the cluster part needs root and is run only when asked (--only cluster)
want() { if [ -z "$ONLY" ]; then [ "$1" != cluster ]; else [ "$ONLY" = "$1" ]; fi; }
case $ONLY in ""|serve|validate|predict|cluster) ;; *) echo "validate_scaling.sh: --only $ONLY?" >&2; exit 2 ;; esac
run() { # np args... (quiet, no checkpoint, output in TMP); prints rt-mpi's summary
    local np=$1
    shift
    if [ "$np" -eq 1 ]; then
        nice -n 10 "$BIN" -q --no-checkpoint -o "$TMP/img.png" "$@"
    else
        nice -n 10 timeout 300 mpirun -np "$np" --oversubscribe --bind-to none "$BIN" -q --no-checkpoint \
            -o "$TMP/img.png" "$@"
    fi
}
jget() { $PY -c 'import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' "$@"; }
summary() { # JSONL of simulate_scaling.py --summary: measured mean [min-max] / predicted
    $PY - "$1" <<'PYEOF'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
def rng(v, scale, fmt):
    v = [x * scale for x in v]
    s = fmt % (sum(v) / len(v))
    return s if len(v) == 1 else s + (" [" + fmt + "-" + fmt + "]") % (min(v), max(v))
print("| job | np | units | rank 0 units | rank 0 busy share | messages to rank 0 | MB to rank 0 | "
      "serve CPU ms | final combination ms |")
print("|---|---|---|---|---|---|---|---|---|")
for r in rows:
    tot = r["units_total_measured"]
    same = all(t == r["units_total_predicted"] for t in tot)
    print("| %s | %d | %s | %.1f / %d | %.1f%% / %.1f%% | %.1f / %d | %s / %.3f | %s / %.2f | %s / %.2f |" % (
        r["label"].split(" -np")[0], r["ranks"],
        ("%d = %d" % (tot[0], r["units_total_predicted"])) if same else ("%s / %d" % (tot, r["units_total_predicted"])),
        r["rank0_units_measured"], r["rank0_units_predicted"], r["rank0_share_measured"], r["rank0_share_predicted"],
        r["messages_measured"], r["messages_predicted"], rng(r["bytes_measured"], 1e-6, "%.3f"),
        r["bytes_predicted"] * 1e-6, rng(r["cpu_measured"], 1e3, "%.2f"), r["cpu_predicted"] * 1e3,
        rng(r["fc_measured"], 1e3, "%.2f"), r["fc_predicted"] * 1e3))
PYEOF
}

echo "validate_scaling: $CORES cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), load $(cut -d' ' -f1-3 /proc/loadavg), binary $BIN"

# ---- rank 0's cost ----------------------------------------------------------------
if want serve; then {
    echo
    echo "== rank 0's cost (--empty-units --serve-only, one-row units, $ROUNDS runs each) =="
    : >"$OUT/serve.tsv"
    for ((r = 1; r <= ROUNDS; r++)); do
        for w in 16 1200 2400; do
            s=$OUT/serve-np8-w$w-r$r.stats.json
            run 8 --empty-units --serve-only --width "$w" --height 4000 --band 1 -s 1 -j 1 --stats "$s" >/dev/null
            printf '%s\t%s\t%s\n' 8 "$w" "$s" >>"$OUT/serve.tsv"
        done
        s=$OUT/serve-np2-w1200-r$r.stats.json
        # no flush interval: every sum comes in the final flush (see below)
        run 2 --empty-units --serve-only --width 1200 --height 2000 --band 1 -s 1 -j 1 --flush-interval 0 \
            --stats "$s" >/dev/null
        printf '%s\t%s\t%s\n' 2 1200 "$s" >>"$OUT/serve.tsv"
    done
    $PY - "$OUT/serve.tsv" "$OUT/serve.json" "$ROOT/tools" <<'PYEOF'
import json, sys
sys.path.insert(0, sys.argv[3])
import simulate_scaling as sim
rows, pk = [], []
for line in open(sys.argv[1]):
    np_, w, path = line.split()
    d = json.load(open(path))
    x = (int(w), d["rank0_messages_in"], d["rank0_bytes_in"], d["rank0_serve_cpu_seconds"],
         d["final_combine_seconds"], d["render_seconds"])
    (rows if np_ == "8" else pk).append(x)
# least squares, no intercept: cpu = a * messages + b * bytes
sxx = sum(m * m for _, m, _, _, _, _ in rows)
syy = sum(b * b for _, _, b, _, _, _ in rows)
sxy = sum(m * b for _, m, b, _, _, _ in rows)
sxc = sum(m * c for _, m, _, c, _, _ in rows)
syc = sum(b * c for _, _, b, c, _, _ in rows)
det = sxx * syy - sxy * sxy
a = (sxc * syy - syc * sxy) / det
b = (syc * sxx - sxc * sxy) / det
# the pack cost: the 1200-pixel runs send all their sums in the final flush
job = sim.Job([0.0] * 2000, 1200, 2000, 1)
m = sim.Model(threads=1, latency=1e-6, bandwidth=float("inf"), service_msg=a, service_byte=b, serve_only=True,
              band=1, probe_miss=0, flush_interval=0)
p0 = sim.simulate(job, 2, m, "bands")
fc = sorted(r[4] for r in pk)
pack = max(0.0, (fc[len(fc) // 2] - p0["final_combine"]) / p0["sums_bytes"])
print("-np 8:")
print("| unit pixels | messages | MB in | serve CPU ms (measured) | a*msgs + b*bytes ms | final comb. ms | render s |")
print("|---|---|---|---|---|---|---|")
for w, msgs, nb, cpu, f, wall in rows:
    print("| %dx1 | %d | %.1f | %.2f | %.2f | %.1f | %.3f |" % (w, msgs, nb / 1e6, cpu * 1e3, (a * msgs + b * nb) * 1e3,
                                                         f * 1e3, wall))
print("-np 2, 1200x1: final combination %s ms" % ", ".join("%.1f" % (x * 1e3) for x in fc))
print("fit: rank 0 costs %.2f us per message + %.3f ns per byte received (serve-thread CPU)" % (a * 1e6, b * 1e9))
print("     a unit's report (32 bytes) costs %.2f us; a worker packs a flush at %.3f ns/byte (median final "
      "combination %.1f ms, %.1f ms of it predicted without packing)" % ((a + 32 * b) * 1e6, pack * 1e9,
                                                                       fc[len(fc) // 2] * 1e3,
                                                                       p0["final_combine"] * 1e3))
json.dump({"msg_s": a, "byte_s": b, "pack_byte_s": pack, "points_np8": rows, "points_np2": pk,
           "source": "validate_scaling.sh --only serve"}, open(sys.argv[2], "w"), indent=1)
PYEOF
} | tee "$OUT/serve.txt"; fi

# ---- predicted vs measured on this machine ------------------------------------------
# A job: width height spp name policy [rt-mpi options]. The policy is the
# model's for what rt-mpi does with those options.
VJOBS=("600 400 16 rows tiles" "800 24 128 tiles tiles" "800 24 128 samples affinity --split samples")
if want validate; then
    [ -f "$OUT/serve.json" ] || { echo "validate_scaling: run the serve part first (no $OUT/serve.json)" >&2; exit 1; }
    PACK=$(jget "$OUT/serve.json" pack_byte_s)
    echo
    echo "== predicted vs measured (-j 1, np > $CORES oversubscribed, yield-when-idle off, $VROUNDS runs each) =="
    : >"$OUT/validate.txt"
    : >"$OUT/validate.jsonl"
    for job in "${VJOBS[@]}"; do
        set -- $job
        W=$1 H=$2 S=$3 NAME=$4 POL=$5
        shift 5
        extra=("$@")
        [ $QUICK -eq 0 ] || S=$((S / 2))
        args=(--width "$W" --height "$H" -s "$S" -j 1 "${extra[@]}")
        # the cost profile: one rank, one thread
        run 1 "${args[@]}" --trace "$OUT/val-$NAME-np1.trace.json" --stats "$OUT/val-$NAME-np1.stats.json" \
            >"$OUT/val-$NAME-np1.out"
        for np in 2 4 8; do
            stats=() traces=()
            for ((r = 1; r <= VROUNDS; r++)); do
                base=$OUT/val-$NAME-np$np-r$r
                run "$np" "${args[@]}" --trace "$base.trace.json" --stats "$base.stats.json" >"$base.out"
                stats+=("$base.stats.json") traces+=("$base.trace.json")
            done
            slow=$(awk -v n="$np" -v c="$CORES" 'BEGIN {print (n > c ? n / c : 1)}')
            $SIM --trace "$OUT/val-$NAME-np1.trace.json" --stats "$OUT/val-$NAME-np1.stats.json" \
                --threads 1 --ranks "$np" --network shm --service-json "$OUT/serve.json" --pack-byte "$PACK" \
                --slowdown "$slow" --compare-policy "$POL" --compare "${stats[@]}" --compare-trace "${traces[@]}" \
                --summary "$OUT/validate.jsonl" \
                --label "$NAME job ${W}x${H}, $S spp${extra[*]:+ (${extra[*]})}, policy $POL -np $np -j 1" |
                tee -a "$OUT/validate.txt"
        done
    done
    echo "== summary: measured mean [min-max] / predicted ==" | tee -a "$OUT/validate.txt"
    summary "$OUT/validate.jsonl" | tee -a "$OUT/validate.txt"
fi

# ---- predictions at scale ---------------------------------------------------------
if want predict; then
    [ -f "$OUT/serve.json" ] || { echo "validate_scaling: run the serve part first (no $OUT/serve.json)" >&2; exit 1; }
    echo
    echo "== set-up, start-up and image writing (1200x800, -s 1; best of 3) =="
    best_mpi="" best_wr="" best_set="" best_up=""
    for r in 1 2 3; do
        # image writing: the PNG's temporary file opened to its rename; the
        # old set-up (checks, scene, BVH build, teardown): -np 1, total -
        # render - writing, now only an upper bound of the render phase's
        strace -f -ttt -e trace=openat,rename -o "$TMP/st" "$BIN" --no-checkpoint -o "$TMP/w.png" --width 1200 \
            --height 800 -s 1 -j "$CORES" -q >"$TMP/one"
        wr=$(awk '/w\.png\.tmp.*O_CREAT/ {t0 = $2} /rename\(.*w\.png/ {t1 = $2} END {printf "%.4f", t1 - t0}' "$TMP/st")
        up=$(sed -n 's/^wall time: *\([0-9.]*\) s render, \([0-9.]*\) s total.*/\2 \1/p' "$TMP/one" |
            awk -v w="$wr" '{printf "%.4f", $1 - $2 - w}')
        # set-up inside the render phase: rank 0's setup_seconds (scene
        # broadcast to the render's start: BVH, camera-ray lists,
        # framebuffer); MPI start-up: the rest of mpirun -np 2's wall time
        # outside render, set-up and writing (launch, MPI_Init, checks, the
        # scene's build and broadcast, MPI_Finalize)
        t0=$(date +%s.%N)
        run 2 --width 1200 --height 800 -s 1 -j 1 --stats "$TMP/s2.json" >/dev/null
        tot=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN {printf "%.4f", b - a}')
        ren=$(jget "$TMP/s2.json" render_seconds)
        set1=$(jget "$TMP/s2.json" setup_seconds)
        mpi=$(awk -v t="$tot" -v r="$ren" -v w="$wr" -v s="$set1" 'BEGIN {x = t - r - w - s; printf "%.4f", (x > 0 ? x : 0)}')
        printf 'run %d: writing %s s (under strace); -np 1 total - render - writing %s s; mpirun -np 2 %s s, render %.4f s, set-up %.4f s -> MPI start-up %s s\n' \
            "$r" "$wr" "$up" "$tot" "$ren" "$set1" "$mpi"
        if [ -z "$best_mpi" ] || awk -v a="$mpi" -v b="$best_mpi" 'BEGIN {exit !(a < b)}'; then best_mpi=$mpi; fi
        if [ -z "$best_wr" ] || awk -v a="$wr" -v b="$best_wr" 'BEGIN {exit !(a < b)}'; then best_wr=$wr; fi
        if [ -z "$best_set" ] || awk -v a="$set1" -v b="$best_set" 'BEGIN {exit !(a < b)}'; then best_set=$set1; fi
        if [ -z "$best_up" ] || awk -v a="$up" -v b="$best_up" 'BEGIN {exit !(a < b)}'; then best_up=$up; fi
    done
    best_set=$(awk -v s="$best_set" 'BEGIN {printf "%.4f", s}')
    echo "set-up (setup_seconds) $best_set s, MPI start-up $best_mpi s, image writing $best_wr s (the best of each);"
    echo "upper bound of the set-up (-np 1 total - render - writing) $best_up s"
    printf '{"setup_s": %s, "setup_upper_s": %s, "startup_s": %s, "write_s": %s}\n' "$best_set" "$best_up" \
        "$best_mpi" "$best_wr" >"$OUT/overhead.json"
    echo
    echo "== calibration: 1200x800, 4 spp, -j $CORES, fastest of 3 =="
    best="" bw=""
    for r in 1 2 3; do
        run 1 --width 1200 --height 800 -s 4 -j "$CORES" --trace "$OUT/cal-r$r.trace.json" \
            --stats "$OUT/cal-r$r.stats.json" >"$OUT/cal-r$r.out"
        w=$(jget "$OUT/cal-r$r.stats.json" render_seconds)
        echo "run $r: $w s render"
        if [ -z "$best" ] || awk -v a="$w" -v b="$bw" 'BEGIN {exit !(a < b)}'; then best=$r bw=$w; fi
    done
    cp "$OUT/cal-r$best.stats.json" "$OUT/cal.stats.json"
    PACK=$(jget "$OUT/serve.json" pack_byte_s)
    # the cost profile: each row's cheapest of the 3 runs (a unit another
    # process preempted looks up to 4x dearer on this shared box)
    common=(--trace "$OUT"/cal-r[123].trace.json --stats "$OUT/cal.stats.json" --threads 16 --ranks 64,256,1024,4096
        --service-json "$OUT/serve.json" --pack-byte "$PACK")
    # 4K jobs with 1 s of work per thread at 1024 x 16 and at 4096 x 16 here
    spp1s=$($PY - "$ROOT/tools" "$OUT"/cal-r[123].trace.json <<'PYEOF'
import sys
sys.path.insert(0, sys.argv[1])
import simulate_scaling as sim
prof = None
for path in sys.argv[2:]:
    p = sim.cost_profile(sim.load_trace(path), 1200, 2, 800)
    prof = p if prof is None else [min(x, y) for x, y in zip(prof, p)]
per_spp = sim.Job(prof, 3840, 2160, 1).total
print(" ".join(str(int(-(-n * 16 // per_spp))) for n in (1024, 4096)))
PYEOF
)
    set -- $spp1s
    jobs=("1200 800 500" "3840 2160 500" "3840 2160 4500" "3840 2160 $1" "3840 2160 $2")
    b4=$(awk -v b="$(jget "$OUT/serve.json" byte_s)" 'BEGIN {printf "%.4g", b / 4}')
    for job in "${jobs[@]}"; do
        set -- $job
        name=$1x$2-$3
        echo
        echo "-- $1x$2, $3 spp: as built is tiles (E: render phase with set-up; E+: also MPI start-up and image writing) --"
        $SIM "${common[@]}" --width "$1" --height "$2" --samples "$3" --setup "$best_set" --startup "$best_mpi" \
            --write "$best_wr" --json "$OUT/predict-$name.json" | tee "$OUT/predict-$name.txt"
        if [ "$name" = 1200x800-500 ]; then
            echo "-- $1x$2, $3 spp, tiles, with the set-up's upper bound ($best_up s) --"
            $SIM "${common[@]}" --width "$1" --height "$2" --samples "$3" --setup "$best_up" \
                --startup "$(awk -v a="$best_mpi" -v s="$best_set" -v u="$best_up" 'BEGIN {x = a + s - u; printf "%.4f", (x > 0 ? x : 0)}')" \
                --write "$best_wr" --policies tiles --json "$OUT/predict-$name-setup-upper.json" |
                tail -n +3 | grep -v '^rank 0' | tee "$OUT/predict-$name-setup-upper.txt"
        fi
        # changes against the farm as built (0.1 s flush, 16 units per rank),
        # for sample ranges (affinity) and column tiles: the v2 farm's 1 s
        # flush and 8 units per rank; a 0.25 s flush; 8 or 32 units per
        # rank; a quarter of rank 0's cost per byte (what per-node
        # aggregation of 4 ranks, or a receive path 4x faster than this
        # shared box's, would give: an assumption)
        for change in "--flush-interval 1 --units-per-rank 8" "--flush-interval 0.25" "--units-per-rank 8" \
            "--units-per-rank 32" "--service-byte $b4"; do
            echo "-- $1x$2, $3 spp: $change --"
            $SIM "${common[@]}" --width "$1" --height "$2" --samples "$3" --setup "$best_set" $change \
                --policies affinity,tiles --json "$OUT/predict-$name-${change// /}.json" | tail -n +3 |
                grep -v '^rank 0' | tee "$OUT/predict-$name-${change// /}.txt"
        done
    done
fi

# ---- across the test cluster's hosts ----------------------------------------------
if want cluster; then
    [ -f "$OUT/serve.json" ] || { echo "validate_scaling: run the serve part first (no $OUT/serve.json)" >&2; exit 1; }
    [ "$(id -u)" -eq 0 ] || { echo "validate_scaling: the cluster part needs root (network namespaces)" >&2; exit 1; }
    PACK=$(jget "$OUT/serve.json" pack_byte_s)
    source "$ROOT/tests/cluster/cluster.sh"
    cluster_up 3 || { echo "validate_scaling: cannot make the test cluster" >&2; exit 1; }
    NET=$(cut -d. -f1-3 <"$RT_CLUSTER/hosts/n1.addr").0/24
    printf 'n1 slots=1\nn2 slots=1\n' >"$TMP/two"
    printf 'n1 slots=2\n' >"$TMP/one2"
    printf 'n1 slots=4\nn2 slots=4\nn3 slots=4\n' >"$TMP/three"
    crun() { # hostfile np args...: mpirun on n1, ranks placed round robin over the hosts
        local hf=$1 np=$2
        shift 2
        cluster_exec n1 nice -n 10 timeout 300 mpirun --hostfile "$hf" --map-by node -np "$np" \
            --mca plm_rsh_agent "$RT_CLUSTER/agent" --mca btl self,vader,tcp --mca btl_tcp_if_include "$NET" \
            --mca oob_tcp_if_include "$NET" --mca mpi_yield_when_idle 0 --bind-to none "$@"
    }
    echo
    echo "== the test cluster: 3 hosts ($(tr '\n' ' ' <"$RT_CLUSTER/hostlist")) on $NET, TCP over veth and a bridge =="
    mpicc -O2 -o "$TMP/pingpong" "$ROOT/tools/mpi_pingpong.c"
    crun "$TMP/two" 2 "$TMP/pingpong" >"$OUT/cluster-net.json"
    crun "$TMP/one2" 2 "$TMP/pingpong" >"$OUT/cluster-net-onehost.json"
    LAT=$(jget "$OUT/cluster-net.json" latency_s)
    BWB=$(jget "$OUT/cluster-net.json" bandwidth_Bps)
    awk -v l="$LAT" -v b="$BWB" -v l1="$(jget "$OUT/cluster-net-onehost.json" latency_s)" \
        -v b1="$(jget "$OUT/cluster-net-onehost.json" bandwidth_Bps)" 'BEGIN {
        printf "MPI ping-pong n1 <-> n2 (TCP): %.1f us one way (half the median round trip of 8 bytes), %.2f GB/s (16 x 4 MiB, best of 5)\n", l * 1e6, b / 1e9
        printf "         the same on n1 alone (shared memory): %.1f us, %.2f GB/s\n", l1 * 1e6, b1 / 1e9 }' |
        tee "$OUT/cluster.txt"
    echo "model: --latency $LAT --bandwidth $BWB (every message as if over TCP; ranks on n1 use shared memory)" |
        tee -a "$OUT/cluster.txt"
    : >"$OUT/cluster.jsonl"
    for job in "${VJOBS[@]:0:2}"; do
        set -- $job
        W=$1 H=$2 S=$3 NAME=$4 POL=$5
        [ $QUICK -eq 0 ] || S=$((S / 2))
        args=(--width "$W" --height "$H" -s "$S" -j 1)
        prof=$OUT/val-$NAME-np1
        if [ ! -f "$prof.trace.json" ] || [ "$(jget "$prof.stats.json" samples)" != "$S" ]; then
            run 1 "${args[@]}" --trace "$prof.trace.json" --stats "$prof.stats.json" >"$prof.out"
        fi
        for np in 4 8; do
            stats=() traces=()
            for ((r = 1; r <= VROUNDS; r++)); do
                base=$OUT/cl-$NAME-np$np-r$r
                crun "$TMP/three" "$np" "$BIN" -q --no-checkpoint -o "$TMP/img.png" "${args[@]}" \
                    --trace "$base.trace.json" --stats "$base.stats.json" >"$base.out"
                stats+=("$base.stats.json") traces+=("$base.trace.json")
            done
            hosts=$($PY -c 'import json,sys; d=json.load(open(sys.argv[1])); print(" ".join(r.get("host", "?") for r in sorted(d["per_rank"], key=lambda r: r["rank"])))' "${stats[0]}" 2>/dev/null || echo "?")
            slow=$(awk -v n="$np" -v c="$CORES" 'BEGIN {print (n > c ? n / c : 1)}')
            $SIM --trace "$prof.trace.json" --stats "$prof.stats.json" --threads 1 --ranks "$np" \
                --latency "$LAT" --bandwidth "$BWB" --service-json "$OUT/serve.json" --pack-byte "$PACK" \
                --slowdown "$slow" --compare-policy "$POL" --compare "${stats[@]}" --compare-trace "${traces[@]}" \
                --summary "$OUT/cluster.jsonl" \
                --label "$NAME job ${W}x${H}, $S spp, policy $POL, ranks on $hosts -np $np -j 1" |
                tee -a "$OUT/cluster.txt"
        done
    done
    echo "== summary across hosts: measured mean [min-max] / predicted ==" | tee -a "$OUT/cluster.txt"
    summary "$OUT/cluster.jsonl" | tee -a "$OUT/cluster.txt"
    cluster_down
fi
