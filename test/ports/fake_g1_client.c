/* SPDX-License-Identifier: Apache-2.0 */
#define _POSIX_C_SOURCE 200809L
#include "fake_g1_client.h"

#include <signal.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#ifndef ROZ_FAKE_G1
#error "ROZ_FAKE_G1: the path of fake_g1, set by the build"
#endif

extern char **environ;

void roz_fake_g1_sleep_ms(unsigned ms)
{
    struct timespec ts = { (time_t)(ms / 1000u), (long)(ms % 1000u) * 1000000L };
    while (nanosleep(&ts, &ts) != 0)
        ;
}

static int read_line(roz_fake_g1_t *f)
{
    if (fgets(f->line, sizeof f->line, f->from) == NULL) {
        f->line[0] = '\0';
        return -1;
    }
    f->line[strcspn(f->line, "\n")] = '\0';
    return 0;
}

int roz_fake_g1_start(roz_fake_g1_t *f, uint32_t domain, const char *const *extra, char *err,
                      size_t errlen)
{
    char dom[16];
    char *argv[24];
    int in[2], out[2], n = 0;
    posix_spawn_file_actions_t fa;

    memset(f, 0, sizeof *f);
    snprintf(dom, sizeof dom, "%u", (unsigned)domain);
    argv[n++] = (char *)(uintptr_t)ROZ_FAKE_G1;
    argv[n++] = (char *)(uintptr_t)"--domain";
    argv[n++] = dom;
    for (size_t i = 0; extra != NULL && extra[i] != NULL && n < 22; i++)
        argv[n++] = (char *)(uintptr_t)extra[i];
    argv[n] = NULL;
    if (pipe(in) != 0 || pipe(out) != 0) {
        snprintf(err, errlen, "fake_g1: no pipes");
        return -1;
    }
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, in[0], 0);
    posix_spawn_file_actions_adddup2(&fa, out[1], 1);
    posix_spawn_file_actions_addclose(&fa, in[1]);
    posix_spawn_file_actions_addclose(&fa, out[0]);
    int rc = posix_spawn(&f->pid, ROZ_FAKE_G1, &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    close(in[0]);
    close(out[1]);
    if (rc != 0) {
        snprintf(err, errlen, "fake_g1: cannot start %s", ROZ_FAKE_G1);
        close(in[1]);
        close(out[0]);
        f->pid = 0;
        return -1;
    }
    f->to = fdopen(in[1], "w");
    f->from = fdopen(out[0], "r");
    if (read_line(f) != 0 || strcmp(f->line, "ready") != 0) {
        snprintf(err, errlen, "fake_g1 on domain %u: no \"ready\" (got \"%s\")", (unsigned)domain,
                 f->line);
        (void)roz_fake_g1_stop(f);
        return -1;
    }
    return 0;
}

int roz_fake_g1_ask(roz_fake_g1_t *f, const char *fmt, ...)
{
    va_list ap;
    if (f->pid == 0)
        return -1;
    va_start(ap, fmt);
    vfprintf(f->to, fmt, ap);
    va_end(ap);
    fputc('\n', f->to);
    if (fflush(f->to) != 0 || read_line(f) != 0)
        return -1;
    if (strncmp(f->line, "ok", 2) == 0 && (f->line[2] == '\0' || f->line[2] == ' '))
        return 0;
    return 1;
}

int roz_fake_g1_stop(roz_fake_g1_t *f)
{
    int status = 0;
    if (f->pid == 0)
        return 0;
    if (f->to != NULL) {
        (void)roz_fake_g1_ask(f, "quit"); /* its "ok" read before its stdout closes */
        fclose(f->to);
    }
    if (f->from != NULL)
        fclose(f->from);
    f->to = f->from = NULL;
    /* it exits on quit or on the end of its stdin; a hung fake is killed */
    for (int i = 0; i < 1000; i++) {
        pid_t r = waitpid(f->pid, &status, WNOHANG);
        if (r == f->pid) {
            f->pid = 0;
            return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        }
        roz_fake_g1_sleep_ms(10);
    }
    kill(f->pid, SIGKILL);
    waitpid(f->pid, &status, 0);
    f->pid = 0;
    return -1;
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

int roz_fake_g1_command(roz_fake_g1_t *f, roz_fake_g1_cmd_t *out)
{
    int rc = roz_fake_g1_ask(f, "command");
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
