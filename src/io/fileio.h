/* fileio.h - atomic file replacement: write to a temporary file in the
 * target's directory, flush and fsync it, then rename over the target. A
 * reader never sees a partial file and a failed write never clobbers the old
 * one. */
#ifndef RT_FILEIO_H
#define RT_FILEIO_H

#include <stdio.h>

typedef struct rt_atomic_file {
    FILE *fp;
    char *tmp_path;
    char *final_path;
} rt_atomic_file;

/* Creates the temporary file (mode 0644 minus umask). */
int rt_atomic_open(rt_atomic_file *f, const char *path);
/* Flushes, fsyncs, closes and renames; on any failure removes the
 * temporary file and returns RT_EIO or RT_ENOSPACE. */
int rt_atomic_commit(rt_atomic_file *f);
/* Closes and removes the temporary file. */
void rt_atomic_abort(rt_atomic_file *f);

/* Checks that a file could be created at path: RT_EINVAL when path is a
 * directory, RT_ENOENT when its directory does not exist, RT_EACCESS when it
 * is not writable. Creates nothing. */
int rt_file_check_writable(const char *path);

/* Reads the whole file (a regular file, a pipe, /dev/stdin) into a malloc'd
 * buffer with one spare NUL byte after *len bytes. RT_EIO (errno kept) when
 * it cannot be opened or read, RT_EOVERFLOW past max bytes. */
int rt_file_read_all(const char *path, size_t max, char **buf, size_t *len);

#endif
