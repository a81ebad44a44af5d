/* SPDX-License-Identifier: Apache-2.0 */
/* The math probe: a controller that, each tick, evaluates every function of
 * roz_math.h on the inputs of math_probe.h and emits the results as metrics,
 * for test_roz_math_wasm.c to compare with the same header built natively
 * and with the host's libm. It commands nothing. */
#include "math_probe.h"
#include "roz_controller.h"

ROZ_PROCESS(tick)
{
    double r[PROBE_COUNT];
    probe_results(tick, r);
    for (int i = 0; i < PROBE_COUNT; i++)
        roz_emit_metric(r[i]);
}
