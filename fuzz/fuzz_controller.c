/* SPDX-License-Identifier: Apache-2.0 */
/* libFuzzer target: the input is a WebAssembly module. It goes through
 * roz_controller_load() exactly as a controller would (roz's own scan,
 * then wasm3's parse, load, link and compile); a module that loads runs
 * process() for a few ticks on a small fuel budget, so inputs that loop
 * forever stop, and its targets go through the safety filter, whose output
 * must stay inside the UR5 manifest. Any crash, sanitizer report or
 * out-of-manifest value is a finding. */
/* white-box: the harness drives the module's private fields directly */
#define ROZ_PRIVATE_ACCESS
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "roz/abi.h"
#include "roz/controller.h"
#include "roz/filter.h"
#include "ur5_manifest.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define TICKS 4
#define FUEL 5000

static roz_controller_t ctl;
static roz_abi_t abi;
static roz_metric_ring_t ring;
static roz_filter_t filt;
static double target[ROZ_CFG_MAX_COMMANDS];
static double state[ROZ_CFG_MAX_STATES];
static double out[ROZ_CFG_MAX_COMMANDS];

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const roz_manifest_t *m = &roz_manifest_ur5;
    roz_budget_t budget = { FUEL, ROZ_BUDGET_OFF, NULL, NULL };
    roz_metric_t drop;

    roz_controller_init(&ctl);
    roz_abi_init(&abi, m, target, &ring);
    for (uint16_t s = 0; s < m->n_states; s++)
        state[s] = m->states[s].default_value;
    abi.state = state;
    if (roz_controller_load(&ctl, data, size, &abi) != ROZ_OK) {
        if (roz_controller_loaded(&ctl) || roz_controller_error(&ctl)[0] == '\0')
            abort(); /* a refusal always says why and leaves nothing loaded */
        roz_controller_unload(&ctl);
        return 0;
    }
    if (roz_controller_set_budget(&ctl, &budget) != ROZ_OK)
        abort();
    if (roz_filter_init(&filt, m) != ROZ_OK)
        abort();
    for (int64_t t = 0; t < TICKS; t++) {
        abi.tick = t;
        int rc = roz_controller_process(&ctl, t);
        if (rc != ROZ_OK && rc != ROZ_ETRAP && rc != ROZ_ETIMEDOUT)
            abort();
        /* the budget is a hard stop: fuel is charged before the work it
         * pays for, so a call that returns used at most its budget, and one
         * charged past it (by one run or bulk memory op) was stopped there */
        if (roz_controller_fuel_used(&ctl) > FUEL && rc != ROZ_ETIMEDOUT)
            abort();
        roz_filter_apply(&filt, target, state, rc == ROZ_OK ? ROZ_STOP_NONE : ROZ_STOP_CONTROLLED,
                         out);
        for (uint16_t i = 0; i < m->n_commands; i++) {
            if (!(out[i] >= m->commands[i].min && out[i] <= m->commands[i].max))
                abort();
        }
        if (rc != ROZ_OK)
            break;
    }
    while (roz_metric_ring_pop(&ring, &drop))
        ;
    roz_controller_unload(&ctl);
    return 0;
}
