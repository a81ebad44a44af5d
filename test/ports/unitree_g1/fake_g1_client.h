/* SPDX-License-Identifier: Apache-2.0 */
/* The G1 port's tests drive the fake robot (test/fakes/unitree_g1, a
 * separate process with its own IDL and CRC) over its stdin/stdout: one
 * request line in, one reply line out (its README.md). */
#ifndef ROZ_TEST_FAKE_G1_CLIENT_H
#define ROZ_TEST_FAKE_G1_CLIENT_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/types.h>

#include "fake_process.h"

/* The running fake: its pid, pipes and last reply (f->line). */
typedef roz_fake_process_t roz_fake_g1_t;

/* Starts fake_g1 (path ROZ_FAKE_G1, set by the build) on @p domain with
 * @p extra options (NULL-terminated list, may be NULL) and waits for its
 * "ready". 0, or -1 with err said. */
int roz_fake_g1_start(roz_fake_g1_t *f, uint32_t domain, const char *const *extra, char *err,
                      size_t errlen);

/* One request; 0 when the reply is "ok ...", 1 when "err ...", -1 when the
 * fake is gone. The reply is in f->line. */
int roz_fake_g1_ask(roz_fake_g1_t *f, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* "quit", then its exit status (-1: it did not exit cleanly). */
int roz_fake_g1_stop(roz_fake_g1_t *f);

/* The fake's command counters: GOOD and BAD_CRC. 0 or -1. */
int roz_fake_g1_commands(roz_fake_g1_t *f, uint64_t *good, uint64_t *bad);

/* The last good command: mode_pr, mode_machine and per slot mode, q, dq,
 * tau, kp, kd. 1 when there is one, 0 before one ("err none"), -1 on error. */
typedef struct roz_fake_g1_cmd {
    unsigned mode_pr, mode_machine;
    unsigned mode[35];
    double   q[35], dq[35], tau[35], kp[35], kd[35];
} roz_fake_g1_cmd_t;
int roz_fake_g1_command(roz_fake_g1_t *f, roz_fake_g1_cmd_t *out);

/* Good command number @p k (1 the first; roz_fake_g1_commands() counts
 * them), while the fake keeps it (the last 2048). 1, or -1. */
int roz_fake_g1_command_at(roz_fake_g1_t *f, uint64_t k, roz_fake_g1_cmd_t *out);

/* Sleep @p ms milliseconds. */
void roz_fake_g1_sleep_ms(unsigned ms);

#endif /* ROZ_TEST_FAKE_G1_CLIENT_H */
