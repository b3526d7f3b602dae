# lib.sh - shared helpers for the end-to-end tests (sourced).
# Every check prints PASS/FAIL with the values involved; the script ends
# with "N passed, N failed" and a non-zero status on any failure.
set -u
PASSED=0
FAILED=0
source "$(dirname "${BASH_SOURCE[0]}")/../../scripts/mpi_env.sh"
export OMPI_MCA_rmaps_base_oversubscribe=1
WORK=$(mktemp -d /tmp/rt-e2e.XXXXXX)
trap 'rm -rf "$WORK"' EXIT

pass() { PASSED=$((PASSED + 1)); echo "PASS: $*"; }
fail() { FAILED=$((FAILED + 1)); echo "FAIL: $*"; }
check_eq() { # name got want (an empty want is a failure: nothing was parsed)
    if [ -n "$3" ] && [ "$2" = "$3" ]; then pass "$1 ($2)"; else fail "$1: got '$2', want '$3'"; fi
}
# A case this machine cannot run. scripts/test.sh sets RT_REQUIRE_ALL=1, so
# in the test command (and CI) a skipped case is a failure, not a silent pass.
skip() {
    if [ "${RT_REQUIRE_ALL:-0}" = 1 ]; then fail "cannot run here: $*"; else echo "SKIP: $*"; fi
}
finish() { # a script that ran no check fails: it tested nothing
    [ $((PASSED + FAILED)) -gt 0 ] || fail "no check ran"
    echo "$PASSED passed, $FAILED failed"
    [ "$FAILED" -eq 0 ]
    exit $?
}
# mpirun with the options a 2-core box needs: ranks may use every core
# (bind-to none) and we may start more ranks than cores.
mpirun_np() { # N args...
    local n=$1
    shift
    timeout 120 "$MPIRUN" -np "$n" --oversubscribe --bind-to none "$@"
}
# A run that must be refused: exit status WANT, one stderr line
# "rt-mpi: error: ..." matching PATTERN (a grep regex), nothing on stdout,
# no file created in $WORK/out and no temporary file left in $WORK.
expect_refusal() { # want label pattern command...
    local want=$1 label=$2 pattern=$3 status lines
    shift 3
    rm -rf "$WORK/out" && mkdir -p "$WORK/out"
    "$@" >"$WORK/usage.out" 2>"$WORK/usage.err"
    status=$?
    lines=$(wc -l <"$WORK/usage.err")
    if [ $status -eq "$want" ] && [ "$lines" -eq 1 ] && grep -q "^rt-mpi: error: .*$pattern" "$WORK/usage.err" &&
        [ ! -s "$WORK/usage.out" ] && [ -z "$(ls -A "$WORK/out")" ] && ! ls "$WORK" | grep -q '\.tmp\.'; then
        pass "$label -> $(cat "$WORK/usage.err")"
    else
        fail "$label: status $status, $lines stderr lines: $(head -c 300 "$WORK/usage.err"), out: $(ls -A "$WORK/out")"
    fi
}
expect_usage_error() { expect_refusal 2 "$@"; } # label pattern command...
# The PID of MPI rank RANK among the processes whose command line contains
# TEXT, found by its environment; waits up to 10 s, prints nothing if none.
rank_pid() { # text rank
    local p i
    for ((i = 0; i < 100; i++)); do
        sleep 0.1
        for p in $(pgrep -f -- "$1"); do
            tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=$2" && { echo "$p"; return; }
        done
    done
}
# The CPU seconds process PID has used (user + system), or nothing once it
# is gone.
cpu_seconds() { # pid
    local stat
    stat=$(cat "/proc/$1/stat" 2>/dev/null) || return
    # fields after the ")" that ends the command name: utime is the 12th, stime the 13th
    awk -v t="$(getconf CLK_TCK)" '{print ($12 + $13) / t}' <<<"${stat##*) }"
}
# Waits until process PID has used SECONDS of CPU (it has done that much
# work, however loaded the machine is); fails if it ends first.
wait_cpu() { # pid seconds
    local c
    while c=$(cpu_seconds "$1") && [ -n "$c" ]; do
        awk -v c="$c" -v s="$2" 'BEGIN {exit !(c >= s)}' && return 0
        sleep 0.05
    done
    return 1
}
# stop_rank_during label signal rank out same-test -- command...: runs the
# command (mpirun, in the background; output in $WORK/label.out and .err)
# and sends the signal to MPI rank RANK (found by rank_pid "-o OUT") once
# it has rendered for half a second of CPU (some units finished: a unit
# takes about 0.1 s), whatever the machine's load. The rank runs at nice
# -5 (as root; else as it was), so that it keeps its share of the work on
# a loaded host: CI once saw it get 0.6 s of CPU in all, 9 of 96 units.
# If it still rendered its whole share and sent its last sums before the
# signal, the job ends well, every byte right (the command same-test
# succeeds) and no rank lost, and nothing was tested: that attempt is said
# so and run again at 0.3 s, then 0.2 s of CPU; not lower, where the rank
# may still be starting (MPI_Init and the scene take about 0.1 s; a rank
# lost there ends the job: e2e_survival.sh's "start"). The caller's checks
# run on the last attempt, so a wrong image, an error exit or a loss is
# never retried. OUT's files (# for a frame number) and its checkpoint are
# removed before each attempt. Sets victim (empty: the rank was not found,
# one failure counted), cpu (at the signal) and status (the command's).
stop_rank_during() {
    local label=$1 sig=$2 rank=$3 out=$4 same=$5 threshold attempt=0 pid
    shift 6
    for threshold in 0.5 0.3 0.2; do
        attempt=$((attempt + 1))
        rm -f ${out//#/*} ${out//#/*}.ckpt "$WORK/$label.done"
        "$@" >"$WORK/$label.out" 2>"$WORK/$label.err" &
        pid=$!
        victim=$(rank_pid "-o $out" "$rank")
        [ -n "$victim" ] || { fail "$label: rank $rank not found"; kill $pid; wait $pid; status=1; return; }
        renice -n -5 -p "$victim" >/dev/null 2>&1 # ahead of the load, so it keeps its share of the work
        wait_cpu "$victim" $threshold
        cpu=$(cpu_seconds "$victim")
        kill -"$sig" "$victim" 2>/dev/null
        wait $pid
        status=$?
        [ $status -eq 0 ] && $same && ! grep -q "^lost ranks:" "$WORK/$label.out" || return 0
        echo "note: $label: attempt $attempt: rank $rank had rendered its whole share and" \
            "$([ -n "$cpu" ] && echo "sent its sums by $cpu s of CPU" || echo ended) (a loaded machine):" \
            "again, at a lower threshold"
    done
}
# A number from --stats' JSON (its first, top-level KEY).
stat_of() { sed -n "0,/^\t\"$2\":/s/^\t\"$2\":\t\([0-9.]*\),*$/\1/p" "$1"; }
# A resume renders only what the checkpoint lacks: the summary says some
# but not all samples were restored, and the resumed run traced fewer ray
# segments than the whole job (the same samples trace the same segments,
# so a resume that rendered everything again has exactly as many) in no
# more units.
rendered_only_missing() { # label summary stats.json whole-job-stats.json
    local restored segs units all_segs all_units
    restored=$(sed -n 's/.*units, \([0-9.]*\)% of the samples restored.*/\1/p' "$2")
    segs=$(stat_of "$3" ray_segments) units=$(stat_of "$3" units)
    all_segs=$(stat_of "$4" ray_segments) all_units=$(stat_of "$4" units)
    if [ -n "$restored" ] && [ -n "$segs" ] && [ -n "$all_segs" ] &&
        awk -v r="$restored" -v s="$segs" -v S="$all_segs" -v u="$units" -v U="$all_units" \
            'BEGIN {exit !(r > 0 && r < 100 && s < S && u <= U)}'; then
        pass "$1: $restored% restored; rendered $units of $all_units units, $segs of $all_segs ray segments"
    else
        fail "$1: resume: '$restored'% restored, $units of $all_units units, $segs of $all_segs segments"
    fi
}
