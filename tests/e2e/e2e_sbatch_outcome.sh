#!/bin/bash
# e2e_sbatch_outcome.sh BIN - scripts/slurm/rt-mpi.sbatch's outcome when the
# launcher fails, run outside Slurm with a stand-in srun on PATH that runs
# the renderer as one process and then exits 137, as srun does when tasks
# of the job were killed although the others finished the image:
#   the renderer wrote the image (its --done-file): the script exits 0;
#   the renderer never ran (no done file): the script exits 137.
BIN=$1
source "$(dirname "$0")/../support/lib.sh"
SCRIPT=$(cd "$(dirname "$0")/../../scripts/slurm" && pwd)/rt-mpi.sbatch
mkdir "$WORK/bin"
# srun [options] BIN args...: runs BIN args... (or not, with FAKE_SRUN_RUN=0), exits 137
cat >"$WORK/bin/srun" <<'SH'
#!/bin/bash
while [ $# -gt 0 ] && [ "$1" != "$RT_MPI_BIN" ]; do shift; done
[ "${FAKE_SRUN_RUN:-1}" = 1 ] && "$@" >/dev/null
exit 137
SH
chmod +x "$WORK/bin/srun"
run_script() { # name -> the script's exit status; its log in WORK/name.log
    PATH=$WORK/bin:$PATH RT_LAUNCHER=srun RT_MPI_BIN=$BIN RT_OUTPUT=$WORK/$1.png RT_WIDTH=32 RT_HEIGHT=16 \
        RT_SAMPLES=2 RT_ARGS=-q bash "$SCRIPT" >"$WORK/$1.log" 2>&1
}
run_script ran
check_eq "srun exits 137 after the image: the script's status" $? 0
grep -q "the launcher exited with 137, but rank 0 finished the image (done " "$WORK/ran.log" &&
    pass "the script says why" || fail "no word of the done file: $(tail -n 3 "$WORK/ran.log")"
[ -s "$WORK/ran.png" ] && pass "the image is there" || fail "no image"
[ ! -e "$WORK/ran.png.ckpt.done" ] && pass "the done file is removed" || fail "the done file is left"
FAKE_SRUN_RUN=0 run_script failed
check_eq "srun exits 137 without an image: the script's status" $? 137
finish
