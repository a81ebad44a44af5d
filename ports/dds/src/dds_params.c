/* SPDX-License-Identifier: Apache-2.0 */
/* The common DDS parameters and the Cyclone configuration built from them:
 * pure functions, no Cyclone call. */
#include "roz/port/dds.h"

#include <stdio.h>
#include <string.h>

#include "roz/hal/params.h"

/* ---- public -------------------------------------------------------------- */

int roz_dds_check_interface(const char *name, char *err, size_t errlen)
{
    if (!roz_params_ifname_valid(roz_params_span(name), ROZ_DDS_IFNAME_MAX,
                                 ROZ_PARAMS_IFNAME_PORTABLE)) {
        snprintf(err, errlen,
                 "parameter network_interface = \"%s\": expected an interface name "
                 "(1..%d characters from A-Z a-z 0-9 _ . : -), such as lo or eth0",
                 name != NULL ? name : "", ROZ_DDS_IFNAME_MAX);
        return ROZ_EINVAL;
    }
    return ROZ_OK;
}

/* The rows the ports' info shows (ROZ_DDS_PARAM_INFO()): the bounds and
 * defaults read here. */
static const roz_port_param_info_t rows[] = { ROZ_DDS_PARAM_INFO("") };
#define ROWS rows, sizeof rows / sizeof rows[0]

int roz_dds_params_parse(roz_dds_params_t *out, const roz_params_t *p, uint32_t default_domain,
                         uint32_t control_rate_hz, char *err, size_t errlen)
{
    const char *iface = roz_params_get_str(p, "network_interface", "lo");
    int rc;

    memset(out, 0, sizeof *out);
    rc = roz_dds_check_interface(iface, err, errlen);
    if (rc != ROZ_OK)
        return rc;
    memcpy(out->network_interface, iface, strlen(iface) + 1);
    if (default_domain > ROZ_DDS_MAX_DOMAIN)
        default_domain = 0;
    rc = roz_params_get_u32(p, "dds_domain", default_domain, 0, ROZ_DDS_MAX_DOMAIN, &out->domain,
                            err, errlen);
    if (rc == ROZ_OK)
        rc = roz_params_get_bool(p, "enable_monitor", 1, &out->enable_monitor, err, errlen);
    if (rc == ROZ_OK)
        rc = roz_params_get_row_u32(p, ROWS, "state_decimation", &out->state_decimation, err,
                                    errlen);
    if (rc != ROZ_OK)
        return rc;
    rc = roz_params_get_u32(p, "command_writer_period_us", 2000, 0, ROZ_DDS_MAX_PERIOD_US,
                            &out->command_writer_period_us, err, errlen);
    if (rc == ROZ_OK && out->command_writer_period_us != 0 &&
        out->command_writer_period_us < ROZ_DDS_MIN_PERIOD_US)
        rc = ROZ_EINVAL;
    if (rc != ROZ_OK) {
        snprintf(err, errlen,
                 "parameter command_writer_period_us = \"%s\": expected 0 (publish as soon as "
                 "the tick writes) or a period in %u..%u us",
                 roz_params_get_str(p, "command_writer_period_us", ""), ROZ_DDS_MIN_PERIOD_US,
                 ROZ_DDS_MAX_PERIOD_US);
        return ROZ_EINVAL;
    }
    rc = roz_params_get_row_u32(p, ROWS, "command_writer_spin_us", &out->command_writer_spin_us,
                                err, errlen);
    if (rc != ROZ_OK)
        return rc;
    if (out->command_writer_spin_us != 0 && out->command_writer_period_us != 0) {
        snprintf(err, errlen,
                 "parameter command_writer_spin_us = \"%s\": only with an event-driven writer "
                 "(command_writer_period_us = 0); this one publishes every %u us",
                 roz_params_get_str(p, "command_writer_spin_us", ""),
                 out->command_writer_period_us);
        return ROZ_EINVAL;
    }
    return roz_cmd_watchdog_param(p, control_rate_hz, out->command_writer_period_us,
                                  &out->command_timeout_us, err, errlen);
}

int roz_dds_config_xml(const char *iface, char *out, size_t len)
{
    char err[8];
    int n;

    if (roz_dds_check_interface(iface, err, sizeof err) != ROZ_OK)
        return ROZ_EINVAL;
    if (strcmp(iface, "lo") == 0)
        n = snprintf(out, len,
                     "<CycloneDDS><Domain Id=\"any\">"
                     "<General><Interfaces><NetworkInterface name=\"lo\"/></Interfaces>"
                     "<AllowMulticast>false</AllowMulticast></General>"
                     "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
                     "<MaxAutoParticipantIndex>%d</MaxAutoParticipantIndex>"
                     "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>"
                     "</Domain></CycloneDDS>",
                     ROZ_DDS_MAX_PARTICIPANT_INDEX);
    else
        n = snprintf(out, len,
                     "<CycloneDDS><Domain Id=\"any\">"
                     "<General><Interfaces><NetworkInterface name=\"%s\"/></Interfaces></General>"
                     "</Domain></CycloneDDS>",
                     iface);
    if (n < 0 || (size_t)n >= len)
        return ROZ_ENOSPC;
    return n;
}
