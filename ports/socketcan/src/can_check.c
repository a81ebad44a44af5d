/* SPDX-License-Identifier: Apache-2.0 */
/* The socketcan port's rules as its registered check_hardware
 * (roz_add_port_rules(), roz/port_rules.h): what roz_manifest_json, and so
 * rozgen, runs on a robot of this port. A file of its own so that the
 * configuration it fills costs nothing where only the port is linked. */
#include "roz/port/can_config.h"

int roz_can_config_check(const roz_manifest_t *m, roz_can_problem_fn report, void *ctx)
{
    static roz_can_config_t cfg; /* host tools, one call at a time */
    return roz_can_config_load(&cfg, m, NULL, report, ctx) == ROZ_OK ? ROZ_OK : ROZ_EINVAL;
}
