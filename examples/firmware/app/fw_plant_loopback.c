/* SPDX-License-Identifier: Apache-2.0 */
/* The demo images' plant (fw_app.h): roz's loopback simulator, which says
 * nothing (no log) and counts every value outside the manifest it receives. */
#include "fw_app.h"
#include "roz/port/loopback.h"

/* Large: static storage, never the stack. */
static roz_loopback_t sim;

static roz_port_t loopback_port(void)
{
    return roz_loopback_port(&sim, NULL, NULL);
}

static uint64_t loopback_violations(void)
{
    return roz_loopback_counters(&sim).violations;
}

const fw_plant_t fw_plant = { loopback_port, loopback_violations };
