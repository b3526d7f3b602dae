#!/bin/bash
# e2e_sbatch_frames.sh BIN - the frame options scripts/slurm/rt-mpi.sbatch
# gives the renderer, run outside Slurm with RT_DRY_RUN=1 (the script
# prints the launcher's command line and runs nothing) and the variables
# Slurm sets for a job or an array task:
#   RT_FRAMES=A-B          -> --frames A-B (one job for the range)
#   --array=A-B            -> --frame <task id>
#   --array=A-B:S          -> --frames <id>-<id+S-1>, clipped at RT_LAST_FRAME
#   RT_CHUNK               -> that many frames per task instead of S
# and refuses RT_FRAMES in an array or a bad RT_CHUNK (exit 2).
BIN=$(readlink -f "$1")
source "$(dirname "$0")/../support/lib.sh"
SCRIPT=$(cd "$(dirname "$0")/../../scripts/slurm" && pwd)/rt-mpi.sbatch
# dry ENV... -> the renderer's words from -o on, one line (the script's status in $?)
dry() {
    local out rc
    out=$(env -u SLURM_ARRAY_TASK_ID -u SLURM_ARRAY_TASK_STEP -u SLURM_ARRAY_TASK_MAX -u RT_FRAMES -u RT_CHUNK -u RT_LAST_FRAME \
        -u RT_OUTPUT -u RT_CHECKPOINT RT_DRY_RUN=1 RT_MPI_BIN="$BIN" SLURM_SUBMIT_DIR="$WORK" SLURM_JOB_ID=7 \
        "$@" bash "$SCRIPT" 2>"$WORK/dry.err")
    rc=$?
    printf '%s\n' "${out#* "$BIN" }"
    return $rc
}
c=$(dry RT_OUTPUT=f.png)
check_eq "one image: no frame option" "$c" "-o f.png -j 1 --checkpoint f.png.ckpt --done-file f.png.ckpt.done"
c=$(dry RT_FRAMES=1-48:2 RT_OUTPUT='t_####.png')
check_eq "RT_FRAMES: one job for the range" "$c" \
    "-o t_####.png --frames 1-48:2 -j 1 --checkpoint t_####.png.ckpt --done-file t_####.png.ckpt.done"
c=$(dry RT_FRAMES=1-3)
check_eq "RT_FRAMES without RT_OUTPUT: a pattern of the job id" "${c%% -j *}" "-o $WORK/rt-mpi-7-####.png --frames 1-3"
c=$(dry SLURM_ARRAY_JOB_ID=5 SLURM_ARRAY_TASK_ID=17 SLURM_ARRAY_TASK_MAX=250)
check_eq "--array=1-250: task 17 renders frame 17, its own checkpoint" "$c" \
    "-o $WORK/rt-mpi-5-####.png --frame 17 -j 1 --checkpoint $WORK/rt-mpi-5-####.png.ckpt.task17 --done-file $WORK/rt-mpi-5-####.png.ckpt.task17.done"
c=$(dry RT_OUTPUT=t.png SLURM_ARRAY_TASK_ID=11 SLURM_ARRAY_TASK_STEP=10 SLURM_ARRAY_TASK_MAX=250)
check_eq "--array=1-250:10: task 11 renders its chunk" "${c%% -j *}" "-o t.png --frames 11-20"
# Slurm gives a task the last task's id (241 for 1-245:10), not the range's end
c=$(dry RT_OUTPUT=t.png SLURM_ARRAY_TASK_ID=241 SLURM_ARRAY_TASK_STEP=10 SLURM_ARRAY_TASK_MAX=241)
check_eq "--array=1-245:10 without RT_LAST_FRAME: a whole chunk" "${c%% -j *}" "-o t.png --frames 241-250"
c=$(dry RT_OUTPUT=t.png RT_LAST_FRAME=245 SLURM_ARRAY_TASK_ID=241 SLURM_ARRAY_TASK_STEP=10 SLURM_ARRAY_TASK_MAX=241)
check_eq "--array=1-245:10, RT_LAST_FRAME=245: the last chunk stops at 245" "${c%% -j *}" "-o t.png --frames 241-245"
c=$(dry RT_OUTPUT=t.png SLURM_ARRAY_TASK_ID=2 SLURM_ARRAY_TASK_STEP=2 SLURM_ARRAY_TASK_MAX=2)
check_eq "--array=0-3:2 (the slurm test's): task 2 renders 2-3" "${c%% -j *}" "-o t.png --frames 2-3"
dry RT_OUTPUT=t.png RT_LAST_FRAME=5 SLURM_ARRAY_TASK_ID=9 SLURM_ARRAY_TASK_STEP=3 >/dev/null
check_eq "RT_LAST_FRAME before the task's first frame: exit" $? 2
c=$(dry RT_OUTPUT=t.png RT_LAST_FRAME=245 SLURM_ARRAY_TASK_ID=245 SLURM_ARRAY_TASK_STEP=4 SLURM_ARRAY_TASK_MAX=245)
check_eq "a chunk of one frame at the end: --frame" "${c%% -j *}" "-o t.png --frame 245"
c=$(dry RT_OUTPUT=t.png RT_CHUNK=3 SLURM_ARRAY_TASK_ID=9 SLURM_ARRAY_TASK_STEP=3 SLURM_ARRAY_TASK_MAX=100)
check_eq "RT_CHUNK=3" "${c%% -j *}" "-o t.png --frames 9-11"
c=$(dry RT_OUTPUT=t.png SLURM_ARRAY_TASK_ID=08)
check_eq "a task id with a leading zero is decimal" "${c%% -j *}" "-o t.png --frame 8"
dry RT_OUTPUT=t.png RT_FRAMES=1-9 SLURM_ARRAY_TASK_ID=3 >/dev/null
check_eq "RT_FRAMES in an array: exit" $? 2
grep -q "RT_FRAMES is for a job that is not an array" "$WORK/dry.err" && pass "and says why" ||
    fail "no reason given: $(cat "$WORK/dry.err")"
for bad in 0 -1 x 1.5; do
    dry RT_OUTPUT=t.png RT_CHUNK="$bad" SLURM_ARRAY_TASK_ID=3 >/dev/null
    check_eq "RT_CHUNK=$bad: exit" $? 2
done
finish
