/* sysinfo.c - host name and peak memory (sysinfo.h). */
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
