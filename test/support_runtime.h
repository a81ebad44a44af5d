/* SPDX-License-Identifier: Apache-2.0 */
/* The runtime fixture: how every C test brings a runtime up, on the
 * loopback simulator or on a port of the test's own. A test fills a config
 * with one of the two config functions, changes what it tests (fuel, stale
 * ticks, a recorder, a log sink), then starts the runtime with
 * roz_test_runtime_start(). Each fails the test with the port's or the
 * runtime's own message, naming the manifest. */
#ifndef ROZ_TEST_SUPPORT_RUNTIME_H
#define ROZ_TEST_SUPPORT_RUNTIME_H

#include "roz/buffer.h"
#include "roz/port/loopback.h"
#include "roz/runtime.h"
#include "support.h"

/* Opens @p port for @p m (no parameters) unless it is open already, and
 * fills @p cfg with the runtime's defaults, @p m, that port and, when @p clk
 * is not NULL, the test clock over it (NULL: the clock is the test's to set). */
void roz_test_runtime_config(roz_runtime_config_t *cfg, const roz_manifest_t *m,
                             roz_port_t port, roz_test_clock_t *clk);

/* Opens @p port for @p m with @p params (may be NULL); fails the test with
 * the port's message. */
void roz_test_port_open(roz_port_t *port, const roz_manifest_t *m, const roz_params_t *params);

/* The parameters of @p kv, one "key=value" (NULL: none), split into @p buf
 * of @p n bytes and @p item. */
roz_params_t roz_test_params_kv(const char *kv, roz_param_t *item, char *buf, size_t n);

/* roz_test_runtime_config() with the test clock over @p clk (from 0, 1 us a
 * read: set clk->step after for another rate), for a run
 * judged by what it does in simulated time: no tick budget and no jitter
 * monitor (the fuel alone decides: the same on every machine). */
void roz_test_physics_config(roz_runtime_config_t *cfg, const roz_manifest_t *m,
                             roz_port_t port, roz_test_clock_t *clk);

/* Opens the loopback port over @p lb for @p m with @p params (may be NULL)
 * and fills @p cfg as roz_test_runtime_config() does, with that port. */
void roz_test_loopback_config(roz_runtime_config_t *cfg, roz_loopback_t *lb,
                              const roz_manifest_t *m, const roz_params_t *params,
                              roz_test_clock_t *clk);

/* Loads @p len bytes at @p w (named @p name in the failure) into @p rt. */
void roz_test_runtime_load(roz_runtime_t *rt, const uint8_t *w, size_t len, const char *name);

/* roz_runtime_init() on @p cfg; then, when @p controller is not NULL, loads
 * ROZ_CONTROLLER_DIR/<controller>.wasm (verified, as every load is); then
 * roz_runtime_start(). */
void roz_test_runtime_start(roz_runtime_t *rt, const roz_runtime_config_t *cfg,
                            const char *controller);

/* roz_test_runtime_start() with the @p len bytes at @p w (named @p name in
 * a failure) for the controller. */
void roz_test_runtime_start_wasm(roz_runtime_t *rt, const roz_runtime_config_t *cfg,
                                 const uint8_t *w, size_t len, const char *name);

/* The frames a port got from @p rt, checked one by one: each value finite
 * and inside its channel's limits, and within the channel's max_rate of the
 * frame before, unless an immediate stop is latched (an e-stop skips the
 * rate cap, roz/filter.h) or, with @p limit_stops_jump, the channel's
 * position limit stopped it since the frame before (the limit may override
 * the rate cap). */
typedef struct {
    const roz_runtime_t *rt;
    const roz_manifest_t *m;
    int limit_stops_jump;
    int have_prev;
    double prev[ROZ_CFG_MAX_COMMANDS];
    uint32_t stops_before[ROZ_CFG_MAX_COMMANDS];
} roz_test_frames_t;

/* Starts the checks over (the next frame has none before it). */
void roz_test_frames_reset(roz_test_frames_t *f, const roz_runtime_t *rt,
                           const roz_manifest_t *m, int limit_stops_jump);

/* Checks @p cmd, the frame of tick @p tick (named in a failure). */
void roz_test_frames_check(roz_test_frames_t *f, const double *cmd, unsigned long long tick);

/* A test port's read op over its self, a roz_buffer_t a thread of the
 * test's own fills: the newest frame's @p n values into @p state;
 * roz_buffer_read()'s result. */
int roz_test_buffer_port_read(void *self, double *state, size_t n);

#endif /* ROZ_TEST_SUPPORT_RUNTIME_H */
