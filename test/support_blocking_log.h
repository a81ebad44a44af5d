/* SPDX-License-Identifier: Apache-2.0 */
/* A log callback that blocks forever on every thread but the test's own
 * (a terminal paused with Ctrl-S, a full pipe, a stalled logger): a thread
 * of roz's that calls it stops there until the test releases it at its end.
 * Lines logged on the test's thread (a drain) are kept. */
#ifndef ROZ_TEST_SUPPORT_BLOCKING_LOG_H
#define ROZ_TEST_SUPPORT_BLOCKING_LOG_H

#include <stddef.h>

#include "roz/log.h"

/* Start blocking other threads; the calling thread is the test's. */
void roz_test_blocking_log_arm(void);
/* Let every blocked thread go and stop blocking. */
void roz_test_blocking_log_release(void);
/* The callback (ctx unused). */
void roz_test_blocking_log(void *ctx, roz_log_level_t level, const char *msg);
/* Calls from other threads since arm (each one blocked). */
unsigned roz_test_blocking_log_blocked(void);
/* Lines logged on the test's thread since arm, and whether one contains
 * @p text. */
unsigned roz_test_blocking_log_lines(void);
int roz_test_blocking_log_saw(const char *text);

#endif /* ROZ_TEST_SUPPORT_BLOCKING_LOG_H */
