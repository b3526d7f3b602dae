/* sysinfo.h - what the operating system says about this process and its
 * node, for the run's summary and reports. */
#ifndef RT_SYSINFO_H
#define RT_SYSINFO_H

#include <stddef.h>

/* This node's name (gethostname), cut to fit n bytes; "" if it has none. */
void rt_sysinfo_hostname(char *buf, size_t n);
/* Peak resident memory of this process in MB (0 when unknown). */
double rt_sysinfo_peak_mb(void);
/* CPU seconds (user and system) of the calling thread so far (0 when
 * unknown). */
double rt_sysinfo_thread_cpu(void);

#endif
