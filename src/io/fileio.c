/* fileio.c - temporary file + fsync + rename. */
#define _POSIX_C_SOURCE 200809L
#include "fileio.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "array.h"
#include "status.h"

static char *dir_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        return strdup(".");
    if (slash == path)
        return strdup("/");
    return strndup(path, (size_t)(slash - path));
}

int rt_atomic_open(rt_atomic_file *f, const char *path)
{
    memset(f, 0, sizeof *f);
    size_t n = strlen(path) + 16;
    f->tmp_path = malloc(n);
    f->final_path = strdup(path);
    if (!f->tmp_path || !f->final_path) {
        rt_atomic_abort(f);
        return RT_ENOMEM;
    }
    snprintf(f->tmp_path, n, "%s.tmp.XXXXXX", path);
    int fd = mkstemp(f->tmp_path);
    if (fd < 0) {
        free(f->tmp_path);
        f->tmp_path = NULL;
        rt_atomic_abort(f);
        return rt_status_from_errno(errno);
    }
    mode_t mask = umask(0);
    umask(mask);
    (void)fchmod(fd, 0666 & ~mask);
    f->fp = fdopen(fd, "wb");
    if (!f->fp) {
        close(fd);
        rt_atomic_abort(f);
        return RT_EIO;
    }
    return RT_OK;
}

int rt_atomic_commit(rt_atomic_file *f)
{
    int st = RT_OK;
    if (fflush(f->fp) != 0 || ferror(f->fp))
        st = rt_status_from_errno(errno);
    if (!st && fsync(fileno(f->fp)) != 0)
        st = rt_status_from_errno(errno);
    if (fclose(f->fp) != 0 && !st)
        st = rt_status_from_errno(errno);
    f->fp = NULL;
    if (!st && rename(f->tmp_path, f->final_path) != 0)
        st = RT_EIO;
    if (st) {
        rt_atomic_abort(f);
        return st;
    }
    /* Make the rename itself durable. */
    char *dir = dir_of(f->final_path);
    if (dir) {
        int dfd = open(dir, O_RDONLY);
        if (dfd >= 0) {
            (void)fsync(dfd);
            close(dfd);
        }
        free(dir);
    }
    free(f->tmp_path);
    free(f->final_path);
    memset(f, 0, sizeof *f);
    return RT_OK;
}

void rt_atomic_abort(rt_atomic_file *f)
{
    if (f->fp)
        fclose(f->fp);
    if (f->tmp_path)
        unlink(f->tmp_path);
    free(f->tmp_path);
    free(f->final_path);
    memset(f, 0, sizeof *f);
}

int rt_file_check_writable(const char *path)
{
    struct stat sb;
    if (!path || !*path)
        return RT_EINVAL;
    if (stat(path, &sb) == 0 && S_ISDIR(sb.st_mode))
        return RT_EINVAL;
    char *dir = dir_of(path);
    if (!dir)
        return RT_ENOMEM;
    int st = RT_OK;
    if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode))
        st = RT_ENOENT;
    else if (access(dir, W_OK | X_OK) != 0)
        st = RT_EACCESS;
    free(dir);
    return st;
}

int rt_file_read_all(const char *path, size_t max, char **buf, size_t *len)
{
    *buf = NULL;
    *len = 0;
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return RT_EIO;
    char *data = NULL;
    size_t n = 0, cap = 0, got;
    int st = RT_OK;
    do {
        if (n + 1 >= cap && (st = rt_array_reserve((void **)&data, &cap, n + 65536, 1)) != RT_OK)
            break;
        got = fread(data + n, 1, cap - n - 1, fp);
        n += got;
        if (n > max)
            st = RT_EOVERFLOW;
    } while (!st && got > 0);
    if (!st && ferror(fp))
        st = RT_EIO;
    int e = errno;
    fclose(fp);
    if (st) {
        free(data);
        errno = e;
        return st;
    }
    if (!data && (data = malloc(1)) == NULL)
        return RT_ENOMEM;
    data[n] = 0;
    *buf = data;
    *len = n;
    return RT_OK;
}
