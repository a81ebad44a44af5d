/* SPDX-License-Identifier: Apache-2.0 */
/* The parameters the DDS ports' conformance fixtures (fixture_unitree_g1.c,
 * fixture_ros2.c) open their port with: loopback, the test's own domain
 * (ROZ_TEST_DDS_DOMAIN), an event-driven writer, a peer timeout of 1 s (a
 * fake starved for a few hundred ms on a loaded machine is not gone) and
 * a command watchdog that never trips on the suite's own pace; then the
 * caller's, which win. Needs <stdio.h>, <stdlib.h> and <string.h>. */
#ifndef ROZ_TEST_DDS_FIXTURE_PARAMS_H
#define ROZ_TEST_DDS_FIXTURE_PARAMS_H

#include <stddef.h>
#include <stdint.h>

#include "roz/port.h"

#ifndef ROZ_TEST_DDS_DOMAIN
#error "ROZ_TEST_DDS_DOMAIN: a domain id of this test's own"
#endif

/* The fixture's parameters and @p params (may be NULL) in @p items (@p max
 * of them, half for the caller's); @p peer_timeout_ms what they say. */
static inline roz_params_t roz_dds_fixture_params(roz_param_t *items, size_t max,
                                                  const roz_params_t *params,
                                                  uint32_t *peer_timeout_ms)
{
    static char domain[16];
    size_t n = 0;

    snprintf(domain, sizeof domain, "%d", ROZ_TEST_DDS_DOMAIN);
    items[n++] = (roz_param_t){ "network_interface", "lo" };
    items[n++] = (roz_param_t){ "dds_domain", domain };
    items[n++] = (roz_param_t){ "command_writer_period_us", "0" };
    items[n++] = (roz_param_t){ "peer_timeout_ms", "1000" };
    /* the suite ticks at its own pace, not a clock's: a pause between two
     * steps is no stuck control loop (the watchdog has tests of its own) */
    items[n++] = (roz_param_t){ "command_timeout_us", "60000000" };
    *peer_timeout_ms = 1000;
    for (size_t i = 0; params != NULL && i < params->n && n < max / 2; i++) {
        items[n++] = params->items[i];
        if (strcmp(params->items[i].key, "peer_timeout_ms") == 0)
            *peer_timeout_ms = (uint32_t)strtoul(params->items[i].value, NULL, 10);
    }
    return (roz_params_t){ items, n };
}

#endif /* ROZ_TEST_DDS_FIXTURE_PARAMS_H */
