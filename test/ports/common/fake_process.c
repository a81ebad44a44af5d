/* SPDX-License-Identifier: Apache-2.0 */
#define _POSIX_C_SOURCE 200809L
#include "fake_process.h"

#include <signal.h>
#include <spawn.h>
#include <stdint.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <setjmp.h>

#include <cmocka.h>

#include "support_spawn.h"

#define MAX_ARGS 24

void roz_fake_sleep_ms(unsigned ms)
{
    struct timespec ts = { (time_t)(ms / 1000u), (long)(ms % 1000u) * 1000000L };
    while (nanosleep(&ts, &ts) != 0)
        ;
}

static int read_line(roz_fake_process_t *f)
{
    if (fgets(f->line, sizeof f->line, f->from) == NULL) {
        f->line[0] = '\0';
        return -1;
    }
    f->line[strcspn(f->line, "\n")] = '\0';
    return 0;
}

int roz_fake_process_start(roz_fake_process_t *f, const char *path, const char *const *args,
                           const char *what, char *err, size_t errlen)
{
    char *argv[MAX_ARGS + 1];
    int in[2], out[2], n = 0;
    posix_spawn_file_actions_t fa;

    memset(f, 0, sizeof *f);
    argv[n++] = (char *)(uintptr_t)path;
    for (size_t i = 0; args != NULL && args[i] != NULL && n < MAX_ARGS; i++)
        argv[n++] = (char *)(uintptr_t)args[i];
    argv[n] = NULL;
    if (pipe(in) != 0) {
        snprintf(err, errlen, "%s: no pipes", what);
        return -1;
    }
    if (pipe(out) != 0) {
        close(in[0]);
        close(in[1]);
        snprintf(err, errlen, "%s: no pipes", what);
        return -1;
    }
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, in[0], 0);
    posix_spawn_file_actions_adddup2(&fa, out[1], 1);
    posix_spawn_file_actions_addclose(&fa, in[1]);
    posix_spawn_file_actions_addclose(&fa, out[0]);
    int rc = roz_test_spawn(&f->pid, &fa, (const char *const *)argv);
    posix_spawn_file_actions_destroy(&fa);
    close(in[0]);
    close(out[1]);
    if (rc != 0) {
        snprintf(err, errlen, "%s: cannot start %s", what, path);
        close(in[1]);
        close(out[0]);
        f->pid = 0;
        return -1;
    }
    f->to = fdopen(in[1], "w");
    f->from = fdopen(out[0], "r");
    if (read_line(f) != 0 || strcmp(f->line, "ready") != 0) {
        snprintf(err, errlen, "%s: no \"ready\" (got \"%s\")", what, f->line);
        (void)roz_fake_process_stop(f);
        return -1;
    }
    return 0;
}

int roz_fake_process_vask(roz_fake_process_t *f, const char *fmt, va_list ap)
{
    if (f->pid == 0)
        return -1;
    vfprintf(f->to, fmt, ap);
    fputc('\n', f->to);
    if (fflush(f->to) != 0 || read_line(f) != 0)
        return -1;
    if (strncmp(f->line, "ok", 2) == 0 && (f->line[2] == '\0' || f->line[2] == ' '))
        return 0;
    return 1;
}

int roz_fake_process_stop(roz_fake_process_t *f)
{
    int status = 0;
    if (f->pid == 0)
        return 0;
    if (f->to != NULL) {
        fputs("quit\n", f->to);
        if (fflush(f->to) == 0)
            (void)read_line(f); /* its "ok" read before its stdout closes */
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
        roz_fake_sleep_ms(10);
    }
    kill(f->pid, SIGKILL);
    waitpid(f->pid, &status, 0);
    f->pid = 0;
    return -1;
}

/* roz_fake_process_vask() with the arguments here. */
static int ask(roz_fake_process_t *f, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int ask(roz_fake_process_t *f, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int rc = roz_fake_process_vask(f, fmt, ap);
    va_end(ap);
    return rc;
}

void roz_fake_process_vmust(roz_fake_process_t *f, const char *who, const char *fmt, va_list ap)
{
    char req[1024];
    vsnprintf(req, sizeof req, fmt, ap);
    if (ask(f, "%s", req) != 0)
        fail_msg("%s: \"%s\" -> \"%s\"", who, req, f->line);
}
