/* SPDX-License-Identifier: Apache-2.0 */
/* The fake G1's Cyclone DDS participant, configured the way roz configures
 * its own: on the loopback interface only, multicast off, 127.0.0.1 as the
 * discovery peer, more participants per host than Cyclone's default of 9;
 * on another interface (when allowed), that interface only. A user's
 * CYCLONEDDS_URI wins and is said so on stderr. The fake's test uses the
 * same participant, so both ends stay on the loopback.
 *
 * Context: the main thread, before any DDS entity exists. */
#ifndef FAKE_G1_DDS_H
#define FAKE_G1_DDS_H

#include <stddef.h>
#include <stdint.h>

#include <dds/dds.h>

/* Domain ids whose default ports fit in 16 bits (7400 + 250 * id + ...). */
#define G1_DDS_MAX_DOMAIN 232u
/* Cyclone's auto participant index limit: the peers probed on 127.0.0.1. */
#define G1_DDS_MAX_PARTICIPANT_INDEX 32u

/* 1 if @p iface is a plausible interface name (1..15 characters of
 * [A-Za-z0-9_.:-]); nothing else reaches the XML. */
int g1_dds_iface_valid(const char *iface);

/* Cyclone's configuration for @p iface into @p buf: 0, or -1 if @p iface
 * is not valid or @p buf is too small. */
int g1_dds_config(char *buf, size_t size, const char *iface);

/* A participant on @p domain over @p iface; a negative dds_return_t, with
 * the reason in @p err, on failure. */
dds_entity_t g1_dds_participant(uint32_t domain, const char *iface, char *err, size_t errlen);

#endif /* FAKE_G1_DDS_H */
