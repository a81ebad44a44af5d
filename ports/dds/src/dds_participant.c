/* SPDX-License-Identifier: Apache-2.0 */
/* The participant: roz's configuration (or the user's), the domain, the
 * participant. */
#include "dds_internal.h"

#include <net/if.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void say(roz_log_fn log, void *ctx, roz_log_level_t level, const char *msg)
{
    if (log != NULL)
        log(ctx, level, msg);
}

int roz_dds_participant_open(roz_dds_participant_t *p, const char *iface, uint32_t domain,
                             const roz_thread_config_t *threads, roz_log_fn log,
                             void *log_ctx, char *err, size_t errlen)
{
    const char *uri = getenv("CYCLONEDDS_URI");
    char msg[ROZ_DDS_CONFIG_MAX + 160];
    int rc;

    memset(p, 0, sizeof *p);
    rc = roz_dds_check_interface(iface, err, errlen);
    if (rc != ROZ_OK)
        return rc;
    if (domain > ROZ_DDS_MAX_DOMAIN) {
        snprintf(err, errlen, "parameter dds_domain = \"%u\": expected an integer in 0..%u",
                 (unsigned)domain, ROZ_DDS_MAX_DOMAIN);
        return ROZ_EINVAL;
    }
    memcpy(p->iface, iface, strlen(iface) + 1);
    p->domain = domain;

    if (uri != NULL && uri[0] != '\0') {
        /* The user's configuration wins: Cyclone reads CYCLONEDDS_URI itself
         * when the participant creates the domain, and roz's settings for
         * Cyclone's threads would be dropped without a word: refused
         * (test_dds_participant) */
        if (threads != NULL && (threads->sched != ROZ_THREAD_OTHER || threads->priority != 0 ||
                                threads->stack_kib != 0 || threads->cpus != 0)) {
            snprintf(err, errlen,
                     "parameter dds_threads_sched/_priority/_stack_kib: CYCLONEDDS_URI is set, "
                     "and Cyclone DDS takes its threads' settings from that file, not from "
                     "roz: set them there (<Threads>) or unset CYCLONEDDS_URI");
            return ROZ_EINVAL;
        }
        p->user_config = 1;
        snprintf(msg, sizeof msg,
                 "dds: CYCLONEDDS_URI is set: Cyclone DDS uses that configuration for domain "
                 "%u, not roz's for network_interface = %s",
                 (unsigned)domain, iface);
        say(log, log_ctx, ROZ_LOG_WARN, msg);
    } else {
        if (if_nametoindex(iface) == 0) {
            snprintf(err, errlen, "parameter network_interface = \"%s\": no such network interface",
                     iface);
            return ROZ_ENOENT;
        }
        rc = roz_dds_config_xml(iface, threads, p->config, sizeof p->config);
        if (rc < 0) {
            snprintf(err, errlen, "parameter network_interface = \"%s\": %s", iface,
                     roz_strerror(rc));
            return rc;
        }
        dds_entity_t d = dds_create_domain((dds_domainid_t)domain, p->config);
        if (d < 0 && d != DDS_RETCODE_PRECONDITION_NOT_MET) {
            snprintf(err, errlen, "dds_domain %u on %s: Cyclone DDS refused the configuration: %s",
                     (unsigned)domain, iface, dds_strretcode(d));
            return ROZ_EIO;
        }
        if (d > 0) {
            p->domain_entity = d;
            snprintf(msg, sizeof msg, "dds: domain %u on %s%s", (unsigned)domain, iface,
                     strcmp(iface, "lo") == 0 ? " (multicast off, peer 127.0.0.1)" : "");
            say(log, log_ctx, ROZ_LOG_INFO, msg);
        } else {
            /* Another part of this process made the domain first: its
             * configuration applies. */
            snprintf(msg, sizeof msg,
                     "dds: domain %u already exists in this process; its configuration applies",
                     (unsigned)domain);
            say(log, log_ctx, ROZ_LOG_WARN, msg);
        }
    }
    dds_entity_t part = dds_create_participant((dds_domainid_t)domain, NULL, NULL);
    if (part < 0) {
        snprintf(err, errlen, "dds_domain %u on %s: no participant: %s", (unsigned)domain, iface,
                 dds_strretcode(part));
        if (p->domain_entity > 0)
            (void)dds_delete(p->domain_entity);
        p->domain_entity = 0;
        return ROZ_EIO;
    }
    p->participant = part;
    return ROZ_OK;
}

void roz_dds_participant_close(roz_dds_participant_t *p)
{
    if (p->participant > 0)
        (void)dds_delete(p->participant);
    if (p->domain_entity > 0)
        (void)dds_delete(p->domain_entity);
    p->participant = 0;
    p->domain_entity = 0;
}
