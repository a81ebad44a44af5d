/* SPDX-License-Identifier: Apache-2.0 */
#define _POSIX_C_SOURCE 200809L
#include "fake_g1_client.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#ifndef ROZ_FAKE_G1
#error "ROZ_FAKE_G1: the path of fake_g1, set by the build"
#endif

void roz_fake_g1_sleep_ms(unsigned ms)
{
    roz_fake_sleep_ms(ms);
}

int roz_fake_g1_start(roz_fake_g1_t *f, uint32_t domain, const char *const *extra, char *err,
                      size_t errlen)
{
    char dom[16], what[48];
    const char *args[24];
    size_t n = 0;

    snprintf(dom, sizeof dom, "%u", (unsigned)domain);
    snprintf(what, sizeof what, "fake_g1 on domain %u", (unsigned)domain);
    args[n++] = "--domain";
    args[n++] = dom;
    for (size_t i = 0; extra != NULL && extra[i] != NULL && n + 1 < 24; i++)
        args[n++] = extra[i];
    args[n] = NULL;
    return roz_fake_process_start(f, ROZ_FAKE_G1, args, what, err, errlen);
}

int roz_fake_g1_ask(roz_fake_g1_t *f, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int rc = roz_fake_process_vask(f, fmt, ap);
    va_end(ap);
    return rc;
}

int roz_fake_g1_stop(roz_fake_g1_t *f)
{
    return roz_fake_process_stop(f);
}

int roz_fake_g1_commands(roz_fake_g1_t *f, uint64_t *good, uint64_t *bad)
{
    unsigned long long g, b;
    if (roz_fake_g1_ask(f, "commands") != 0 || sscanf(f->line, "ok %llu %llu", &g, &b) != 2)
        return -1;
    *good = g;
    *bad = b;
    return 0;
}

static int parse_command(roz_fake_g1_t *f, int rc, roz_fake_g1_cmd_t *out);

int roz_fake_g1_command(roz_fake_g1_t *f, roz_fake_g1_cmd_t *out)
{
    return parse_command(f, roz_fake_g1_ask(f, "command"), out);
}

int roz_fake_g1_command_at(roz_fake_g1_t *f, uint64_t k, roz_fake_g1_cmd_t *out)
{
    int rc = roz_fake_g1_ask(f, "command_at %llu", (unsigned long long)k);
    if (rc == 1)
        return -1;
    return parse_command(f, rc, out);
}

static int parse_command(roz_fake_g1_t *f, int rc, roz_fake_g1_cmd_t *out)
{
    if (rc == 1 && strcmp(f->line, "err none") == 0)
        return 0;
    if (rc != 0)
        return -1;
    char *p = f->line + 2, *end;
    out->mode_pr = (unsigned)strtoul(p, &end, 10);
    out->mode_machine = (unsigned)strtoul(end, &end, 10);
    for (int i = 0; i < 35; i++) {
        out->mode[i] = (unsigned)strtoul(end, &end, 10);
        out->q[i] = strtod(end, &end);
        out->dq[i] = strtod(end, &end);
        out->tau[i] = strtod(end, &end);
        out->kp[i] = strtod(end, &end);
        out->kd[i] = strtod(end, &p);
        if (p == end)
            return -1;
        end = p;
    }
    return 1;
}
