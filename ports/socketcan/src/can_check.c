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

/* The rule ids of the socketcan port's rules, "<id>\t<what it refuses>", NULL-ended:
 * its registration's RULE_IDS (roz_manifest_json --list-rules). */
const char *const roz_can_rule_ids[] = {
    "can-param\tsocketcan port: a [hardware.params] key of a CAN robot is missing or "
    "malformed (an entry, a number, a range, a layout)",
    "can-id\tsocketcan port: two joints share a CAN id or its low byte (a reply's "
    "id), or one is master_id",
    "can-joint\tsocketcan port: a hardware joint name it cannot use, none at all, or "
    "a joint without a channel",
    "can-channel\tsocketcan port: a channel that is not JOINT/<type> of a hardware "
    "joint with a type it carries",
    "can-range\tsocketcan port: an actuator's range does not hold the limits of one "
    "of its joint's channels",
    "can-bus\tsocketcan port: one joint's frames overrun the bus in a round, or "
    "reply_timeout_us is shorter than two command intervals",
    NULL,
};
