/* SPDX-License-Identifier: Apache-2.0 */
/* Private, for benchmarks only (bench/tick): a controller compiled without
 * its fuel charges, to measure what metering costs. Never used by roz
 * itself. Such an instance refuses every budget but ROZ_BUDGET_OFF for both
 * fuel and deadline (roz_controller_set_budget returns ROZ_EINVAL), so
 * nothing can believe it is bounded. */
#ifndef ROZ_CONTROLLER_BENCH_H
#define ROZ_CONTROLLER_BENCH_H

#include "roz/controller.h"

/* As roz_controller_load(), without fuel charges. */
int roz__controller_load_unmetered(roz_controller_t *c, const uint8_t *wasm, size_t len,
                                   roz_abi_t *abi);

#endif /* ROZ_CONTROLLER_BENCH_H */
