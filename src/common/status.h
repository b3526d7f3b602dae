/* status.h - the status codes every module returns, and their messages.
 * Modules never print or exit; they return one of these and the caller
 * (main or the farm layer) decides how to report it. */
#ifndef RT_STATUS_H
#define RT_STATUS_H

#define RT_STATUS_TABLE(X)                                                    \
    X(RT_OK, 0, "success")                                                    \
    X(RT_ENOMEM, -1, "out of memory")                                         \
    X(RT_EINVAL, -2, "invalid argument")                                      \
    X(RT_EIO, -3, "input/output error")                                       \
    X(RT_EFORMAT, -4, "malformed data")                                       \
    X(RT_EVERSION, -5, "unsupported format version")                          \
    X(RT_EOVERFLOW, -6, "size too large")                                     \
    X(RT_EPNG, -7, "PNG encoder error")                                       \
    X(RT_EMISMATCH, -8, "data belongs to a different job")                    \
    X(RT_ECHECKSUM, -9, "checksum mismatch (corrupt or truncated)")           \
    X(RT_ENOSPACE, -10, "no space left on device")                            \
    X(RT_EUNSUPPORTED, -11, "unsupported")                                    \
    X(RT_ENOENT, -12, "directory does not exist")                             \
    X(RT_EACCESS, -13, "directory is not writable")                         \
    X(RT_ERANGE, -14, "out of range")                                         \
    X(RT_ENOFILE, -15, "no such file")                                        \
    X(RT_EIMAGE_TYPE, -16, "not a PNG or JPEG file")                          \
    X(RT_EIMAGE_TRUNCATED, -17, "image file is truncated")                    \
    X(RT_EIMAGE_CORRUPT, -18, "image data is corrupt")                        \
    X(RT_EIMAGE_CRC, -19, "PNG chunk with a bad CRC (corrupt file)")          \
    X(RT_EIMAGE_EMPTY, -20, "image has zero width or height")                 \
    X(RT_EIMAGE_LIMIT, -21, "image exceeds the texture pixel limit")          \
    X(RT_EIMAGE_CMYK, -22, "CMYK JPEG is not supported (save it as RGB)")     \
    X(RT_EIMAGE_DEPTH, -23, "12- or 16-bit JPEG is not supported")            \
    X(RT_ENOJPEG, -24, "this build reads no JPEG (built without libjpeg-turbo)")

typedef enum rt_status {
#define RT_STATUS_ENUM(name, value, msg) name = value,
    RT_STATUS_TABLE(RT_STATUS_ENUM)
#undef RT_STATUS_ENUM
} rt_status;

/* The status for a failed system call's errno: RT_ENOSPACE for a full disk
 * or quota, RT_EIO otherwise. */
int rt_status_from_errno(int e);

/* Human-readable text for a status code; never NULL. */
const char *rt_status_str(int status);

#endif
