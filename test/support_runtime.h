/* SPDX-License-Identifier: Apache-2.0 */
/* Helpers for tests that run the runtime on the loopback simulator. */
#ifndef ROZ_TEST_SUPPORT_RUNTIME_H
#define ROZ_TEST_SUPPORT_RUNTIME_H

#include "roz/loopback.h"
#include "roz/runtime.h"
#include "support.h"

/* Opens the loopback port over lb for m (with params, may be NULL) and fills
 * cfg with the runtime defaults, that port and the test clock clk. Fails the
 * test, naming the manifest and the port's message, if the port refuses. */
void roz_test_loopback_config(roz_runtime_config_t *cfg, roz_loopback_t *lb,
                              const roz_manifest_t *m, const roz_params_t *params,
                              roz_test_clock_t *clk);

#endif /* ROZ_TEST_SUPPORT_RUNTIME_H */
