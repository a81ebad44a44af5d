/* SPDX-License-Identifier: Apache-2.0 */
#define _POSIX_C_SOURCE 200809L
#include "rozrun_stand.h"

#include <fcntl.h>
#include <setjmp.h>
#include <signal.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#include "support_spawn.h"

static void sleep_20ms(void)
{
    struct timespec ts = { 0, 20000000L };
    while (nanosleep(&ts, &ts) != 0)
        ;
}

void roz_rozrun_stand(const char *rozrun, const char *robot, const char *port,
                      const char *controller, uint32_t domain, int ticks, const char *out,
                      const char *record, void (*watch)(void *ctx), void *ctx, char *text,
                      size_t len)
{
    char dom[32], nticks[16];
    snprintf(dom, sizeof dom, "dds_domain=%u", (unsigned)domain);
    snprintf(nticks, sizeof nticks, "%d", ticks);
    const char *argv[] = { rozrun,
                           "--robot", robot,
                           "--port", port,
                           "--param", "network_interface=lo",
                           "--param", dom,
                           "--param", "peer_timeout_ms=5000",
                           /* the command watchdog at its longest: a loaded
                            * machine may deschedule the tick past the default
                            * (the ports' tests have the watchdog's cases) */
                           "--param", "command_timeout_us=60000000",
                           "--controller", controller,
                           "--ticks", nticks,
                           "--budget-us", "off",
                           "--stale-ticks", "250",
                           record != NULL ? "--record" : NULL, record,
                           NULL };
    assert_int_equal(roz_rozrun_spawn(argv, out, watch, ctx, text, len), 0);
}

static pid_t running;

long roz_rozrun_pid(void)
{
    return (long)running;
}

/* Reads @p out into @p text (printed). */
static void read_out(const char *out, char *text, size_t len)
{
    FILE *f = fopen(out, "r");
    assert_non_null(f);
    size_t n = fread(text, 1, len - 1, f);
    text[n] = '\0';
    fclose(f);
    print_message("%s", text);
}

int roz_rozrun_spawn(const char *const *argv, const char *out, void (*watch)(void *ctx),
                     void *ctx, char *text, size_t len)
{
    posix_spawn_file_actions_t fa;
    pid_t pid;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, out, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    assert_int_equal(roz_test_spawn(&pid, &fa, argv), 0);
    posix_spawn_file_actions_destroy(&fa);
    running = pid;

    /* while it runs: what the robot gets (a hang guard of 60 s) */
    int status = 0, done = 0;
    for (int ms = 0; ms < 60000 && !done; ms += 20) {
        if (waitpid(pid, &status, WNOHANG) == pid) {
            done = 1;
            break;
        }
        if (watch != NULL)
            watch(ctx);
        sleep_20ms();
    }
    running = 0;
    if (!done) {
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        fail_msg("%s did not finish in 60 s", argv[0]);
    }
    read_out(out, text, len);
    assert_true(WIFEXITED(status));
    return WEXITSTATUS(status);
}

void roz_rozrun_replay(const char *rozrun, const char *recording, const char *controller,
                       int ticks, const char *out, char *text, size_t len)
{
    const char *argv[] = { rozrun, "--replay", recording, "--controller", controller, NULL };
    posix_spawn_file_actions_t fa;
    char want[64];
    pid_t pid;
    int status = 0;

    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, out, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    assert_int_equal(roz_test_spawn(&pid, &fa, argv), 0);
    posix_spawn_file_actions_destroy(&fa);
    assert_int_equal(waitpid(pid, &status, 0), pid);
    read_out(out, text, len);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 0);
    snprintf(want, sizeof want, "ticks replayed         %d\n", ticks);
    assert_non_null(strstr(text, want));
    assert_non_null(strstr(text, "result                 identical"));
}
