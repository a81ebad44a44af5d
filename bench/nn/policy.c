/* SPDX-License-Identifier: Apache-2.0 */
/* The policy through roz_nn.h and the nn imports (bench/nn). */
#include "roz_controller.h"

#include "policy.h"

ROZ_PROCESS(tick)
{
    roz_emit_metric((double)bench_infer(tick));
}
