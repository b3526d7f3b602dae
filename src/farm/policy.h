/* policy.h - the farm's defaults and policy values, the one place they are
 * written: the CLI's defaults and help text, the job set-up, the worker and
 * the server read them here. Plain literals, so the help can quote them
 * (RT_POLICY_STR). */
#ifndef RT_FARM_POLICY_H
#define RT_FARM_POLICY_H

#define RT_POLICY_PREFETCH 2         /* units a worker keeps in flight */
#define RT_POLICY_LEASE 5            /* s of silence before rank 0 takes a rank for lost */
#define RT_POLICY_FLUSH_INTERVAL 0.1 /* s: a worker sends its sums at least this often */
#define RT_POLICY_FLUSH_NEVER 0      /* a flush interval meaning: only when asked or full */
#define RT_POLICY_FLUSH_MB 64        /* MiB of held sums that make a worker send them */
#define RT_POLICY_MAX_BAND 16        /* most rows of an automatic band */
#define RT_POLICY_UNITS_PER_RANK 16  /* units a pass wants per rank, for balance */
#define RT_POLICY_FRAMES_IN_FLIGHT 4 /* a frame job: frames with units out at most (their sums on rank 0) */
#define RT_POLICY_START_WAIT 60      /* s rank 0 waits for every rank at a start-up step before ending the job */

#define RT_POLICY_STR_(x) #x
#define RT_POLICY_STR(x) RT_POLICY_STR_(x)

#endif
