/* SPDX-License-Identifier: Apache-2.0 */
#define _POSIX_C_SOURCE 200809L
#include "roz/module.h"

#include <errno.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "roz/error.h"
#include "roz/format.h"

extern char **environ;

/* ---- private ------------------------------------------------------------- */

static int read_all(const char *path, const char *shown, uint8_t *buf, size_t cap, size_t *len,
                    char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        roz_format(err, errlen, "cannot read %s: %s", shown, strerror(errno));
        return ROZ_EIO;
    }
    size_t n = fread(buf, 1, cap, f);
    int more = n == cap && fgetc(f) != EOF;
    int failed = ferror(f);
    fclose(f);
    if (failed) {
        roz_format(err, errlen, "cannot read %s", shown);
        return ROZ_EIO;
    }
    if (more) {
        roz_format(err, errlen, "%s: larger than %zu bytes", shown, cap);
        return ROZ_ENOSPC;
    }
    *len = n;
    return ROZ_OK;
}

static int assemble_wat(const char *path, uint8_t *buf, size_t cap, size_t *len, char *err,
                        size_t errlen)
{
    char tmp[] = "/tmp/roz-wat-XXXXXX";
    int fd = mkstemp(tmp);
    if (fd < 0) {
        roz_format(err, errlen, "%s: cannot create a temporary file: %s", path, strerror(errno));
        return ROZ_EIO;
    }
    close(fd);
    /* posix_spawnp takes char *const argv[]: give it writable copies */
    char prog[] = "wat2wasm", out_flag[] = "-o";
    char *in = strdup(path);
    if (in == NULL) {
        unlink(tmp);
        roz_format(err, errlen, "out of memory");
        return ROZ_EIO;
    }
    char *args[] = { prog, in, out_flag, tmp, NULL };
    pid_t pid;
    int status = 0;
    int rc = posix_spawnp(&pid, "wat2wasm", NULL, NULL, args, environ);
    free(in);
    if (rc != 0) {
        unlink(tmp);
        roz_format(err, errlen, "%s: cannot run wat2wasm (Debian package wabt): %s", path,
                   strerror(rc));
        return ROZ_EIO;
    }
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        unlink(tmp);
        roz_format(err, errlen, "%s: wat2wasm refused it (its message is above)", path);
        return ROZ_EIO;
    }
    rc = read_all(tmp, path, buf, cap, len, err, errlen);
    unlink(tmp);
    return rc;
}

/* ---- public -------------------------------------------------------------- */

int roz_module_read_file(const char *path, uint8_t *buf, size_t cap, size_t *len, char *err,
                         size_t errlen)
{
    size_t n = strlen(path);
    if (n > 4 && strcmp(path + n - 4, ".wat") == 0)
        return assemble_wat(path, buf, cap, len, err, errlen);
    return read_all(path, path, buf, cap, len, err, errlen);
}
