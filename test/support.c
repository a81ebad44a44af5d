/* SPDX-License-Identifier: Apache-2.0 */
#include "support.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#define SLOTS 8
#define MAX_MODULE (256 * 1024)

/* @p path into the next of the rotating buffers; NULL when it cannot be
 * opened. */
static const uint8_t *read_wasm(const char *path, size_t *len)
{
    static uint8_t bufs[SLOTS][MAX_MODULE];
    static unsigned next;

    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    uint8_t *buf = bufs[next++ % SLOTS];
    *len = fread(buf, 1, MAX_MODULE, f);
    fclose(f);
    if (*len == 0 || *len == MAX_MODULE)
        fail_msg("%s: empty or too large", path);
    return buf;
}

const uint8_t *roz_test_wasm_file(const char *path, size_t *len)
{
    const uint8_t *w = read_wasm(path, len);

    if (w == NULL)
        fail_msg("cannot open %s", path);
    return w;
}

const uint8_t *roz_test_wasm_or_null(const char *dir, const char *name, size_t *len)
{
    char path[4096]; /* a clone may sit at any depth */

    snprintf(path, sizeof path, "%s/%s.wasm", dir, name);
    return read_wasm(path, len);
}

const uint8_t *roz_test_wasm(const char *dir, const char *name, size_t *len)
{
    char path[4096];

    snprintf(path, sizeof path, "%s/%s.wasm", dir, name);
    return roz_test_wasm_file(path, len);
}

const uint8_t *roz_test_controller(const char *name, size_t *len)
{
    return roz_test_wasm(ROZ_CONTROLLER_DIR, name, len);
}

uint64_t roz_test_clock(void *ctx)
{
    roz_test_clock_t *c = ctx;
    uint64_t t = c->now;
    c->now += c->step;
    return t;
}
