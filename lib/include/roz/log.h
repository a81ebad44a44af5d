/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/log.h
 * @brief The log callback through which roz reports warnings and errors.
 *
 * roz never prints by itself: the application sets a callback (host tools set
 * one that writes to stderr). Messages are short, one line, no newline.
 */
#ifndef ROZ_LOG_H
#define ROZ_LOG_H

#include "roz/config.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum roz_log_level {
    ROZ_LOG_ERROR = 0,
    ROZ_LOG_WARN,
    ROZ_LOG_INFO,
} roz_log_level_t;

/** Called only from the application's own calls (start-up, shut-down,
 *  roz_runtime_log_drain()), never from the tick or a thread roz runs: it may
 *  block (a host sink writing a line to stderr). */
typedef void (*roz_log_fn)(void *ctx, roz_log_level_t level, const char *msg);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_LOG_H */
