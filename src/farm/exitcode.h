/* exitcode.h - the program's exit codes, the one table of them (README's
 * "Exit status" says more to users). The farm ends the job with them
 * (rt_farm_fail, rt_farm_exit); the app chooses them. */
#ifndef RT_FARM_EXITCODE_H
#define RT_FARM_EXITCODE_H

/* X(name, code, text): text is the --help line (usage.c prints it; a '\n'
 * goes on at the items' column). */
#define RT_EXIT_CODES(X)                                                                                           \
    X(RT_EXIT_OK, 0, "Done")                                                                                       \
    X(RT_EXIT_RUNTIME, 1, "Runtime failure")                                                                       \
    X(RT_EXIT_USAGE, 2, "Bad input (one line: rt-mpi: error: ...)")                                               \
    X(RT_EXIT_CHECKPOINT, 3, "Checkpoint refused (it belongs to another job)")                                     \
    /* stopped by SIGTERM/SIGINT/SIGUSR1 after saving: EX_TEMPFAIL */                                              \
    X(RT_EXIT_INTERRUPTED, 75, "Interrupted by SIGTERM, SIGINT or SIGUSR1 after saving the\n"                      \
                               "checkpoint: rerun with --resume")

typedef enum rt_exit_code {
#define RT_EXIT_ENUM(name, value, text) name = value,
    RT_EXIT_CODES(RT_EXIT_ENUM)
#undef RT_EXIT_ENUM
} rt_exit_code;

#endif
