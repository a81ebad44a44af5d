/* SPDX-License-Identifier: Apache-2.0 */
#define _POSIX_C_SOURCE 200809L
#include "support_wat.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include <cmocka.h>

#include "roz/error.h"
#include "roz/module.h"

size_t roz_test_wat(const char *wat, uint8_t *buf, size_t cap)
{
    char dir[] = "/tmp/roz_test_wat_XXXXXX", path[64], err[256];
    size_t len = 0;
    FILE *f;

    if (mkdtemp(dir) == NULL)
        fail_msg("roz_test_wat: cannot make a temporary folder");
    snprintf(path, sizeof path, "%s/m.wat", dir);
    f = fopen(path, "w");
    if (f == NULL || fputs(wat, f) == EOF || fclose(f) != 0)
        fail_msg("roz_test_wat: cannot write %s", path);
    int rc = roz_module_read_file(path, buf, cap, &len, err, sizeof err);
    unlink(path);
    rmdir(dir);
    if (rc != ROZ_OK)
        fail_msg("wat2wasm: %s", err);
    return len;
}
