/* clock.h - the one clock every layer times with. */
#ifndef RT_CLOCK_H
#define RT_CLOCK_H

/* Monotonic seconds since an arbitrary origin. */
double rt_now(void);

#endif
