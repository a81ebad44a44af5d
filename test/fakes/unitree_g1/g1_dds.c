/* SPDX-License-Identifier: Apache-2.0 */
#include "g1_dds.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int g1_dds_iface_valid(const char *iface)
{
    size_t n = strlen(iface);
    if (n == 0 || n > 15)
        return 0;
    for (size_t i = 0; i < n; i++) {
        char c = iface[i];
        int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                 c == '_' || c == '.' || c == ':' || c == '-';
        if (!ok)
            return 0;
    }
    return 1;
}

int g1_dds_config(char *buf, size_t size, const char *iface)
{
    int n;
    if (!g1_dds_iface_valid(iface))
        return -1;
    if (strcmp(iface, "lo") == 0) {
        /* Without multicast nothing is discovered unless a peer is named;
         * 127.0.0.1 makes Cyclone probe the unicast discovery ports of
         * participant indices 0..MaxAutoParticipantIndex on this host. */
        n = snprintf(buf, size,
                     "<CycloneDDS><Domain id=\"any\">"
                     "<General><Interfaces><NetworkInterface name=\"lo\"/></Interfaces>"
                     "<AllowMulticast>false</AllowMulticast></General>"
                     "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
                     "<MaxAutoParticipantIndex>%u</MaxAutoParticipantIndex>"
                     "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>"
                     "</Domain></CycloneDDS>",
                     G1_DDS_MAX_PARTICIPANT_INDEX);
    } else {
        n = snprintf(buf, size,
                     "<CycloneDDS><Domain id=\"any\">"
                     "<General><Interfaces><NetworkInterface name=\"%s\"/></Interfaces></General>"
                     "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
                     "<MaxAutoParticipantIndex>%u</MaxAutoParticipantIndex></Discovery>"
                     "</Domain></CycloneDDS>",
                     iface, G1_DDS_MAX_PARTICIPANT_INDEX);
    }
    return n > 0 && (size_t)n < size ? 0 : -1;
}

dds_entity_t g1_dds_participant(uint32_t domain, const char *iface, char *err, size_t errlen)
{
    char config[1024];
    const char *uri = getenv("CYCLONEDDS_URI");
    if (domain > G1_DDS_MAX_DOMAIN) {
        snprintf(err, errlen, "domain %u is not a DDS domain id 0..%u", domain,
                 G1_DDS_MAX_DOMAIN);
        return DDS_RETCODE_BAD_PARAMETER;
    }
    if (uri != NULL && uri[0] != '\0') {
        fprintf(stderr, "fake_g1: CYCLONEDDS_URI is set: Cyclone DDS is configured by it, "
                        "not for interface %s\n", iface);
    } else {
        if (g1_dds_config(config, sizeof config, iface) != 0) {
            snprintf(err, errlen, "interface '%s' is not an interface name", iface);
            return DDS_RETCODE_BAD_PARAMETER;
        }
        dds_entity_t d = dds_create_domain(domain, config);
        if (d < 0) {
            snprintf(err, errlen, "DDS domain %u on %s: %s", domain, iface, dds_strretcode(d));
            return d;
        }
    }
    dds_entity_t p = dds_create_participant(domain, NULL, NULL);
    if (p < 0)
        snprintf(err, errlen, "DDS participant on domain %u: %s", domain, dds_strretcode(p));
    return p;
}
