/* SPDX-License-Identifier: Apache-2.0 */
/* The model's include tree, read before MuJoCo reads it: MuJoCo follows
 * <include file=...> as often as it is written (fifteen files each
 * including the next four times grew it to 4 GB, then std::bad_alloc), and
 * reads /dev/zero until memory runs out. This walk applies rozgen's limits
 * (codegen/rozgen/mjcf.py: 16 deep, 256 includes and 32 MiB of XML in all,
 * regular files only), so that rozgen --check and the port refuse the same
 * models. It finds include elements by their text (comments skipped): a
 * model it passes may hold fewer includes than it counted, never more. */
#define _POSIX_C_SOURCE 200809L
#include "mjcf_scan.h"

#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "roz/error.h"
#include "roz/format.h"

typedef struct {
    char path[ROZ_MJCF_PATH_MAX];
    int  depth;
} scan_file_t;

typedef struct {
    scan_file_t *files; /* every file to read: the model, then its includes */
    size_t       n;
    size_t       bytes; /* read in all */
    char        *buf;   /* one file's bytes, MJCF_MAX_BYTES + 1 */
} scan_t;

/* The file's bytes into s->buf, within what the total leaves; its length,
 * or -1 with the reason in @p err. */
static long read_file(scan_t *s, const char *path, const char *shown, char *err,
                      size_t errlen)
{
    struct stat st;
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        roz_format(err, errlen, "%s: cannot be read", shown);
        return -1;
    }
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        roz_format(err, errlen, "%s: not a regular file", shown);
        return -1;
    }
    size_t left = ROZ_MJCF_MAX_BYTES - s->bytes, got = 0;
    while (got <= left) {
        ssize_t r = read(fd, s->buf + got, left + 1 - got);
        if (r < 0) {
            close(fd);
            roz_format(err, errlen, "%s: cannot be read", shown);
            return -1;
        }
        if (r == 0)
            break;
        got += (size_t)r;
    }
    close(fd);
    if (got > left) {
        roz_format(err, errlen, "%s: the model's XML passes %d bytes in all (the model and "
                   "its includes; this port's limit)", shown, ROZ_MJCF_MAX_BYTES);
        return -1;
    }
    s->bytes += got;
    return (long)got;
}

/* Each <include file="..."> of one file's text, queued for reading. */
static int queue_includes(scan_t *s, const char *text, size_t len, const char *dir,
                          const scan_file_t *from, char *err, size_t errlen)
{
    size_t i = 0;
    while (i < len) {
        const char *lt = memchr(text + i, '<', len - i);
        if (lt == NULL)
            break;
        i = (size_t)(lt - text);
        if (len - i >= 4 && memcmp(text + i, "<!--", 4) == 0) {
            const char *end = NULL;
            for (size_t k = i + 4; k + 3 <= len; k++) {
                if (memcmp(text + k, "-->", 3) == 0) {
                    end = text + k + 3;
                    break;
                }
            }
            if (end == NULL)
                break;
            i = (size_t)(end - text);
            continue;
        }
        i++;
        if (len - i < 8 || memcmp(text + i, "include", 7) != 0 ||
            (text[i + 7] != ' ' && text[i + 7] != '\t' && text[i + 7] != '\n' &&
             text[i + 7] != '\r' && text[i + 7] != '/' && text[i + 7] != '>'))
            continue;
        /* the element's attributes, up to its '>' */
        const char *gt = memchr(text + i, '>', len - i);
        size_t end = gt != NULL ? (size_t)(gt - text) : len;
        const char *name = NULL;
        size_t name_len = 0;
        for (size_t k = i + 7; k + 6 <= end; k++) {
            if (memcmp(text + k, "file", 4) != 0 || (text[k - 1] != ' ' && text[k - 1] != '\t' &&
                                                     text[k - 1] != '\n' && text[k - 1] != '\r'))
                continue;
            size_t q = k + 4;
            while (q < end && (text[q] == ' ' || text[q] == '\t' || text[q] == '\n'))
                q++;
            if (q >= end || text[q] != '=')
                continue;
            q++;
            while (q < end && (text[q] == ' ' || text[q] == '\t' || text[q] == '\n'))
                q++;
            if (q >= end || (text[q] != '"' && text[q] != '\''))
                continue;
            const char *close = memchr(text + q + 1, text[q], end - q - 1);
            if (close == NULL)
                break;
            name = text + q + 1;
            name_len = (size_t)(close - name);
            break;
        }
        i = end;
        if (name == NULL)
            continue; /* MuJoCo refuses an include without a file itself */
        if (s->n > ROZ_MJCF_MAX_INCLUDES) {
            roz_format(err, errlen, "%s: more than %d includes in all (this port's limit)",
                       from->path, ROZ_MJCF_MAX_INCLUDES);
            return ROZ_EINVAL;
        }
        if (from->depth + 1 > ROZ_MJCF_MAX_DEPTH) {
            roz_format(err, errlen, "%s: includes nested more than %d deep", from->path,
                       ROZ_MJCF_MAX_DEPTH);
            return ROZ_EINVAL;
        }
        scan_file_t *f = &s->files[s->n];
        size_t dl = name_len > 0 && name[0] == '/' ? 0 : strlen(dir);
        if (dl + name_len + 1 > sizeof f->path) {
            roz_format(err, errlen, "%s: an include's path is longer than %d bytes", from->path,
                       ROZ_MJCF_PATH_MAX - 1);
            return ROZ_EINVAL;
        }
        memcpy(f->path, dir, dl);
        memcpy(f->path + dl, name, name_len);
        f->path[dl + name_len] = '\0';
        f->depth = from->depth + 1;
        s->n++;
    }
    return ROZ_OK;
}

int roz__mjcf_scan(const char *model, char *err, size_t errlen)
{
    scan_t s = { 0 };
    char dir[ROZ_MJCF_PATH_MAX];
    int rc = ROZ_OK;
    size_t ml = strlen(model);
    if (ml + 1 > sizeof dir) {
        roz_format(err, errlen, "%s: the path is longer than %d bytes", model,
                   ROZ_MJCF_PATH_MAX - 1);
        return ROZ_EINVAL;
    }
    /* MuJoCo takes every include's path from the main model's folder */
    const char *slash = strrchr(model, '/');
    size_t dl = slash != NULL ? (size_t)(slash - model) + 1 : 0;
    memcpy(dir, model, dl);
    dir[dl] = '\0';
    s.files = calloc(ROZ_MJCF_MAX_INCLUDES + 2u, sizeof *s.files);
    s.buf = malloc((size_t)ROZ_MJCF_MAX_BYTES + 1u);
    if (s.files == NULL || s.buf == NULL) {
        roz_format(err, errlen, "%s: no memory to read the model", model);
        rc = ROZ_ENOMEM;
        goto out;
    }
    memcpy(s.files[0].path, model, ml + 1);
    s.n = 1;
    for (size_t k = 0; k < s.n && rc == ROZ_OK; k++) {
        const scan_file_t *f = &s.files[k];
        char shown[ROZ_MJCF_PATH_MAX + 32];
        roz_format(shown, sizeof shown, k == 0 ? "%s" : "<include file=\"%s\">", f->path);
        long len = read_file(&s, f->path, shown, err, errlen);
        if (len < 0)
            rc = ROZ_EINVAL;
        else
            rc = queue_includes(&s, s.buf, (size_t)len, dir, f, err, errlen);
    }
out:
    free(s.files);
    free(s.buf);
    return rc;
}
