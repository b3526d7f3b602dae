/* sysinfo.c - host name, peak memory and a thread's CPU time (sysinfo.h). */
#define _GNU_SOURCE /* RUSAGE_THREAD */
#include "sysinfo.h"

#include <sys/resource.h>
#include <unistd.h>

void rt_sysinfo_hostname(char *buf, size_t n)
{
    if (gethostname(buf, n) != 0)
        buf[0] = 0;
    buf[n - 1] = 0;
}

double rt_sysinfo_peak_mb(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0)
        return 0;
    return (double)ru.ru_maxrss / 1024.0; /* Linux reports KiB */
}

double rt_sysinfo_thread_cpu(void)
{
#ifdef RUSAGE_THREAD
    struct rusage ru;
    if (getrusage(RUSAGE_THREAD, &ru) != 0)
        return 0;
    return (double)ru.ru_utime.tv_sec + 1e-6 * ru.ru_utime.tv_usec + (double)ru.ru_stime.tv_sec +
           1e-6 * ru.ru_stime.tv_usec;
#else
    return 0;
#endif
}
