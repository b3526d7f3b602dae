#!/bin/bash
# test_slurm.sh BIN - ctest driver (label: slurm) for scripts/slurm/rt-mpi.sbatch.
#
# Starts a private single-node Slurm (tests/slurm/slurm_env.sh) and checks:
#   0  the cluster runs MPI jobs:  mpirun -np 2 hostname  /  srun --mpi=pmix -n 2 hostname
#   a  an image rendered through sbatch (mpirun and srun launchers) is
#      byte-identical to a direct run of BIN
#   b  time-limit warning: SIGUSR1 to the batch shell (what --signal=B:USR1@N
#      does; sent here with `scancel --signal=USR1 --batch`) -> renderer exits
#      75 with a checkpoint -> the script requeues the job -> it resumes with
#      --resume -> final image == direct run
#   c  preemption: `scontrol requeue` of the running job (Slurm SIGTERMs every
#      process; srun launcher) -> job runs again, resumes -> final image == direct
#   d  frames in one job: RT_FRAMES=0-3 (--frames) -> four files of the
#      output pattern, each == a direct render of that frame alone (--frame N)
#   e  frames in an array job: --array=0-1 (a frame per task) and
#      --array=0-3:2 (a chunk of two per task) -> each file == direct
#
# Exit 0 all passed, 1 a check failed, 77 skipped (Slurm missing and cannot be
# installed: not root / no apt).  Every wait is bounded; typical run < 1 min.
#
# Environment knobs:
#   RT_SLURM_PREEMPT_SAMPLES   first guess of samples for b/c (default 64); it
#                              is scaled up until a direct render takes at
#                              least RT_SLURM_PREEMPT_MIN_S seconds (default 6)
#   RT_SLURM_PREEMPT_SIZE      WxH for b/c (default 64x48)
#   RT_SLURM_TEST_KEEP=1       keep the work dir (always kept on failure)
set -euo pipefail

if [[ $# -ne 1 ]]; then
    echo "usage: $0 RT_MPI_BINARY" >&2
    exit 2
fi
BIN=$(readlink -f "$1")
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
SCRIPT=$ROOT/scripts/slurm/rt-mpi.sbatch
T_START=$SECONDS

# shellcheck source=slurm_env.sh source-path=SCRIPTDIR
source "$HERE/slurm_env.sh"

PASSED=0
FAILED=0
WORK=""
pass() { PASSED=$((PASSED + 1)); echo "PASS: $*"; }
fail() { FAILED=$((FAILED + 1)); echo "FAIL: $*"; }
note() { echo "---- [$((SECONDS - T_START))s] $*"; }

cleanup() {
    local rc=$?
    set +e
    if (( FAILED > 0 || rc != 0 )) && [[ -n ${SLURM_ENV_DIR:-} && -d ${SLURM_ENV_DIR:-} ]]; then
        _slurm_dump_logs
    fi
    slurm_down
    if [[ -n $WORK && -d $WORK ]]; then
        if (( FAILED > 0 || rc != 0 )) || [[ ${RT_SLURM_TEST_KEEP:-0} == 1 ]]; then
            echo "work dir kept: $WORK"
        else
            rm -rf "$WORK"
        fi
    fi
    exit "$rc"
}
trap cleanup EXIT

[[ -x $BIN ]] || { echo "FAIL: renderer binary '$1' not found or not executable"; exit 1; }
[[ -f $SCRIPT ]] || { echo "FAIL: $SCRIPT missing"; exit 1; }

# ------------------------------------------------------------------ setup
note "install"
if ! slurm_install; then
    if [[ $(id -u) -ne 0 ]] || ! command -v apt-get >/dev/null 2>&1; then
        echo "SKIP: Slurm not installed and cannot install it here"
        trap - EXIT
        # In the test command (RT_REQUIRE_ALL=1) a skip is a failure.
        [[ ${RT_REQUIRE_ALL:-0} == 1 ]] && exit 1
        exit 77
    fi
    echo "FAIL: slurm_install"
    exit 1
fi
note "slurm_up"
slurm_up

WORK=$(mktemp -d "${TMPDIR:-/tmp}/rt-slurm-test.XXXXXX")
cd "$WORK"
if [[ $(id -u) -eq 0 ]]; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
export OMPI_MCA_pml=${OMPI_MCA_pml:-ob1}
export RT_MPI_BIN=$BIN

now_ms() { date +%s%3N; }
secs() { printf '%d.%03d' $(($1 / 1000)) $(($1 % 1000)); }

# job_field JOB FIELD -> value of FIELD=... in `scontrol show job`
job_field() {
    { timeout 20 scontrol -o show job "$1" 2>/dev/null || true; } |
        tr ' ' '\n' | sed -n "s/^$2=//p" | head -n 1
}

# wait_job JOB TIMEOUT_S -> 0 when the job reached a final state (printed in
# $JOB_STATE), 1 on timeout.  A requeued job passes through PENDING again.
JOB_STATE=""
wait_job() {
    local j=$1 limit=$2 t0=$SECONDS
    while (( SECONDS - t0 < limit )); do
        JOB_STATE=$(job_field "$j" JobState)
        case $JOB_STATE in
            COMPLETED|FAILED|CANCELLED|TIMEOUT|NODE_FAIL|OUT_OF_MEMORY|BOOT_FAIL|DEADLINE|PREEMPTED)
                return 0 ;;
        esac
        sleep 0.25
    done
    return 1
}

# wait_for TENTHS CMD... -> poll CMD every 0.1 s, give up after TENTHS/10 s
wait_for() {
    local n=$1; shift
    until "$@"; do
        (( n-- > 0 )) || return 1
        sleep 0.1
    done
}

job_is_running() { [[ $(job_field "$1" JobState) == RUNNING ]]; }

show_log() { [[ -f $1 ]] && { echo "     --- $1:"; sed 's/^/     | /' "$1" | tail -n 40; }; return 0; }

submit() {  # submit OUTFILE_PREFIX [sbatch args...] -> job id on stdout
    local name=$1; shift
    timeout 30 sbatch --parsable --chdir="$WORK" --output="$WORK/$name-%j.out" "$@"
}

# ------------------------------------------- 0: the cluster runs MPI jobs
note "0: trivial MPI jobs"
cat >"$WORK/hello-mpirun.sh" <<'EOF'
#!/bin/bash
mpirun -np 2 hostname
EOF
cat >"$WORK/hello-srun.sh" <<EOF
#!/bin/bash
srun --mpi=${SLURM_ENV_MPI} -n 2 hostname
EOF
for l in mpirun srun; do
    t0=$(now_ms)
    j=$(submit "hello-$l" -n 2 "$WORK/hello-$l.sh") || { fail "0 $l: sbatch failed"; continue; }
    if wait_job "$j" 60 && [[ $JOB_STATE == COMPLETED ]] &&
       [[ $(grep -c -x "$SLURM_ENV_NODE" "$WORK/hello-$l-$j.out") -eq 2 ]]; then
        pass "0 $l: job $j printed hostname twice ($(secs $(( $(now_ms) - t0 )))s submit->done)"
    else
        fail "0 $l: job $j state '${JOB_STATE}', output:"; show_log "$WORK/hello-$l-$j.out"
    fi
done

# ------------------------------------- a: sbatch render == direct render
note "a: direct render"
t0=$(now_ms)
if ! timeout 120 "$BIN" -o "$WORK/direct.png" --width 64 --height 48 -s 4 -q >"$WORK/direct.txt"; then
    fail "a: direct run of $BIN failed"; show_log "$WORK/direct.txt"
fi
note "a: direct render took $(secs $(( $(now_ms) - t0 )))s"
for l in mpirun srun; do
    t0=$(now_ms)
    j=$(RT_LAUNCHER=$l RT_OUTPUT="$WORK/a-$l.png" RT_WIDTH=64 RT_HEIGHT=48 RT_SAMPLES=4 RT_ARGS=-q \
        submit "a-$l" "$SCRIPT") || { fail "a $l: sbatch failed"; continue; }
    if ! wait_job "$j" 120; then
        fail "a $l: job $j not finished after 120 s (state '$JOB_STATE')"; show_log "$WORK/a-$l-$j.out"
        continue
    fi
    dt=$(secs $(( $(now_ms) - t0 )))
    ec=$(job_field "$j" ExitCode)
    if [[ $JOB_STATE != COMPLETED || $ec != 0:0 ]]; then
        fail "a $l: job $j $JOB_STATE exit $ec"; show_log "$WORK/a-$l-$j.out"
    elif [[ -f $WORK/direct.png ]] && cmp -s "$WORK/direct.png" "$WORK/a-$l.png"; then
        pass "a $l: job $j image == direct ($(stat -c %s "$WORK/direct.png") bytes, ${dt}s submit->done)"
    else
        fail "a $l: job $j image differs from direct run (or missing): $(cmp "$WORK/direct.png" "$WORK/a-$l.png" 2>&1)"
        show_log "$WORK/a-$l-$j.out"
    fi
done

# ------------------------------ b/c: reference render, slow enough to interrupt
IFS=x read -r PW PH <<<"${RT_SLURM_PREEMPT_SIZE:-64x48}"
PS=${RT_SLURM_PREEMPT_SAMPLES:-64}
MIN_MS=$(( ${RT_SLURM_PREEMPT_MIN_S:-6} * 1000 ))
# A checkpoint after every completed row, so the test can signal as soon as
# the checkpoint file exists.
RT_SLURM_PREEMPT_ARGS="--checkpoint-interval 0"
note "b/c: renderer args for the interrupted jobs: -q ${RT_SLURM_PREEMPT_ARGS}"
note "b/c: calibrating a direct render of ${PW}x${PH} that takes >= $((MIN_MS / 1000)) s"
REF_OK=0
for _ in 1 2 3 4; do
    t0=$(now_ms)
    if ! timeout 150 "$BIN" -o "$WORK/ref.png" --width "$PW" --height "$PH" -s "$PS" -q >"$WORK/ref.txt"; then
        fail "b/c: direct reference run (-s $PS) failed"; show_log "$WORK/ref.txt"; break
    fi
    ms=$(( $(now_ms) - t0 ))
    note "direct -s $PS: $(secs "$ms")s"
    if (( ms >= MIN_MS )); then REF_OK=1; break; fi
    # scale samples towards ~1.5x the minimum duration (factor 2..16)
    f=$(( (MIN_MS * 3 / 2) / (ms > 0 ? ms : 1) + 1 ))
    (( f < 2 )) && f=2
    (( f > 16 )) && f=16
    PS=$(( PS * f ))
done
(( REF_OK )) || fail "b/c: could not make a direct render last ${MIN_MS} ms (last -s $PS)"

# preempt_case NAME LAUNCHER HOW ; HOW = usr1 (scancel --signal=USR1 --batch)
#                                       or requeue (scontrol requeue)
preempt_case() {
    local name=$1 launcher=$2 how=$3 j t0 ckpt=$WORK/$1.png.ckpt trigger restarts ec
    rm -f "$WORK/$name.png" "$ckpt"
    t0=$(now_ms)
    j=$(RT_LAUNCHER=$launcher RT_OUTPUT="$WORK/$name.png" RT_CHECKPOINT="$ckpt" \
        RT_WIDTH=$PW RT_HEIGHT=$PH RT_SAMPLES=$PS RT_ARGS="-q ${RT_SLURM_PREEMPT_ARGS}" \
        submit "$name" "$SCRIPT") ||
        { fail "$name: sbatch failed"; return; }
    # Running, then: the first checkpoint is there.
    if ! wait_for 600 job_is_running "$j"; then
        fail "$name: job $j never started"; show_log "$WORK/$name-$j.out"; return
    fi
    if ! wait_for 15 test -e "$ckpt"; then
        fail "$name: no checkpoint appeared"; show_log "$WORK/$name-$j.out"; return
    fi
    trigger="checkpoint present"
    local st
    st=$(job_field "$j" JobState)
    if [[ $st != RUNNING ]]; then
        fail "$name: job $j was already $st before it could be interrupted (${PW}x${PH} -s $PS); raise RT_SLURM_PREEMPT_MIN_S / RT_SLURM_PREEMPT_SAMPLES"
        show_log "$WORK/$name-$j.out"; return
    fi
    local t_sig rc=0
    t_sig=$(now_ms)
    case $how in
        usr1)    timeout 20 scancel --signal=USR1 --batch "$j" || rc=$? ;;
        requeue) timeout 20 scontrol requeue "$j" || rc=$? ;;
    esac
    if (( rc != 0 )); then
        fail "$name: signalling job $j ($how) failed with $rc (state $(job_field "$j" JobState))"
        show_log "$WORK/$name-$j.out"
    fi
    note "$name: job $j signalled ($how) $(secs $(( t_sig - t0 )))s after submit ($trigger)"
    if ! wait_job "$j" 120; then
        fail "$name: job $j not finished 120 s after the signal (state '$JOB_STATE')"
        show_log "$WORK/$name-$j.out"; return
    fi
    restarts=$(job_field "$j" Restarts)
    ec=$(job_field "$j" ExitCode)
    local info
    info="job $j: ${restarts} restart(s), final $JOB_STATE $ec, $(secs $(( $(now_ms) - t_sig )))s signal->done, ${PW}x${PH} -s $PS"
    if [[ $JOB_STATE != COMPLETED || $ec != 0:0 ]]; then
        fail "$name: $info"; show_log "$WORK/$name-$j.out"
    elif [[ ${restarts:-0} -lt 1 ]]; then
        fail "$name: job finished before it was interrupted ($info); raise RT_SLURM_PREEMPT_SAMPLES / RT_SLURM_PREEMPT_MIN_S"
        show_log "$WORK/$name-$j.out"
    elif ! grep -q 'checkpoint .* found: resuming' "$WORK/$name-$j.out"; then
        fail "$name: restarted run did not pass --resume ($info)"; show_log "$WORK/$name-$j.out"
    elif [[ $how == usr1 ]] && ! grep -q 'renderer exited with 75' "$WORK/$name-$j.out"; then
        fail "$name: renderer did not exit 75 after SIGUSR1 ($info)"; show_log "$WORK/$name-$j.out"
    elif (( REF_OK )) && cmp -s "$WORK/ref.png" "$WORK/$name.png"; then
        pass "$name: resumed image == direct ($info)"
    else
        fail "$name: resumed image differs from direct (or missing) ($info): $(cmp "$WORK/ref.png" "$WORK/$name.png" 2>&1)"
        show_log "$WORK/$name-$j.out"
    fi
}

note "b: SIGUSR1 to the batch shell (time-limit warning), mpirun"
preempt_case b-usr1 mpirun usr1
note "c: scontrol requeue of the running job (preemption), srun"
preempt_case c-requeue srun requeue

# ------------------------------------------ d/e: frame sequences
# book 2's bouncing spheres move with each frame's time, so the frames differ
FRAME_ARGS="--scene bouncing-spheres --width 32 --height 18 -s 2"
note "d/e: direct renders of frames 0-3 (${FRAME_ARGS})"
for f in 0 1 2 3; do
    # shellcheck disable=SC2086
    timeout 120 "$BIN" $FRAME_ARGS -q --frame "$f" -o "$WORK/ref_####.png" >"$WORK/ref-frames.txt" 2>&1 ||
        { fail "d/e: direct render of frame $f failed"; show_log "$WORK/ref-frames.txt"; }
done

# same_frames NAME FIRST LAST INFO -> pass when NAME_####.png of frames
# FIRST..LAST are each byte-identical to ref_####.png
same_frames() {
    local name=$1 f n bad=""
    for (( f = $2; f <= $3; f++ )); do
        n=$(printf '%04d' "$f")
        cmp -s "$WORK/ref_$n.png" "$WORK/${name}_$n.png" || bad="$bad $n"
    done
    if [[ -z $bad ]]; then
        pass "$name: frames $2-$3 == direct --frame N ($4)"
    else
        fail "$name: frames differ from direct (or missing):$bad ($4)"
    fi
}

note "d: RT_FRAMES=0-3 in one job"
j=$(RT_OUTPUT="$WORK/d_####.png" RT_FRAMES=0-3 RT_ARGS="-q $FRAME_ARGS" submit d "$SCRIPT") ||
    { fail "d: sbatch failed"; j=""; }
if [[ -n $j ]]; then
    if ! wait_job "$j" 120; then
        fail "d: job $j not finished after 120 s (state '$JOB_STATE')"; show_log "$WORK/d-$j.out"
    elif [[ $JOB_STATE != COMPLETED || $(job_field "$j" ExitCode) != 0:0 ]]; then
        fail "d: job $j $JOB_STATE exit $(job_field "$j" ExitCode)"; show_log "$WORK/d-$j.out"
    else
        same_frames d 0 3 "job $j"
        grep -q -- '--frames 0-3' "$WORK/d-$j.out" || fail "d: the job did not pass --frames 0-3"
    fi
fi

# array_case NAME ARRAY TASKS... : sbatch --array=ARRAY, every task
# COMPLETED with exit 0, then frames 0-3 (or 0-1) == direct
array_case() {
    local name=$1 spec=$2 j t last=0 ok=1; shift 2
    j=$(RT_OUTPUT="$WORK/${name}_####.png" RT_ARGS="-q $FRAME_ARGS" timeout 30 sbatch --parsable \
        --chdir="$WORK" --output="$WORK/$name-%A_%a.out" --array="$spec" "$SCRIPT") ||
        { fail "$name: sbatch --array=$spec failed"; return; }
    j=${j%%;*}
    for t in "$@"; do
        if ! wait_job "${j}_$t" 120; then
            fail "$name: task ${j}_$t not finished after 120 s (state '$JOB_STATE')"; ok=0
        elif [[ $JOB_STATE != COMPLETED || $(job_field "${j}_$t" ExitCode) != 0:0 ]]; then
            fail "$name: task ${j}_$t $JOB_STATE exit $(job_field "${j}_$t" ExitCode)"; ok=0
        fi
        (( ok )) || show_log "$WORK/$name-${j}_$t.out"
        last=$t
    done
    (( ok )) || return
    [[ $spec == *:* ]] && last=$(( last + ${spec##*:} - 1 ))
    same_frames "$name" 0 "$last" "array job $j, --array=$spec"
}
note "e1: --array=0-1, a frame per task"
array_case e1 0-1 0 1
note "e2: --array=0-3:2, a chunk of two frames per task"
array_case e2 0-3:2 0 2

note "done in $((SECONDS - T_START))s"
echo "$PASSED passed, $FAILED failed"
(( FAILED == 0 ))
