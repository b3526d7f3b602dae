/* status.c - maps status codes to messages (one table, see status.h). */
#include "status.h"

#include <errno.h>

const char *rt_status_str(int status)
{
    switch (status) {
#define RT_STATUS_CASE(name, value, msg) \
    case value:                          \
        return msg;
        RT_STATUS_TABLE(RT_STATUS_CASE)
#undef RT_STATUS_CASE
    }
    return "unknown error";
}

int rt_status_from_errno(int e) { return e == ENOSPC || e == EDQUOT ? RT_ENOSPACE : RT_EIO; }
