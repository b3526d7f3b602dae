/* exitcode.h - the program's exit codes, the one table of them (README
 * "Exit codes" says the same to users). The farm ends the job with them
 * (rt_farm_fail, rt_farm_exit); the app chooses them. */
#ifndef RT_FARM_EXITCODE_H
#define RT_FARM_EXITCODE_H

#define RT_EXIT_CODES(X)                                                                                           \
    X(RT_EXIT_OK, 0, "image written")                                                                              \
    X(RT_EXIT_RUNTIME, 1, "runtime failure (I/O, memory, MPI)")                                                    \
    X(RT_EXIT_USAGE, 2, "bad input: nothing rendered, no file touched")                                           \
    X(RT_EXIT_CHECKPOINT, 3, "checkpoint refused")                                                                 \
    /* stopped by SIGTERM/SIGINT/SIGUSR1 after saving: rerun with --resume (EX_TEMPFAIL) */                        \
    X(RT_EXIT_INTERRUPTED, 75, "interrupted, checkpoint saved")

typedef enum rt_exit_code {
#define RT_EXIT_ENUM(name, value, text) name = value,
    RT_EXIT_CODES(RT_EXIT_ENUM)
#undef RT_EXIT_ENUM
} rt_exit_code;

#endif
