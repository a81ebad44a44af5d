/* SPDX-License-Identifier: Apache-2.0 */
/* The fake ROS 2 robot's Cyclone DDS participant, configured the way roz
 * configures its own for the loopback: the lo interface only, multicast
 * off, 127.0.0.1 as the discovery peer, more participants per host than
 * Cyclone's default. A user's CYCLONEDDS_URI wins and is said so on stderr.
 * The fake's own test takes the same participant, so both ends stay on the
 * loopback.
 *
 * Context: the main thread, before any DDS entity exists. */
#ifndef FAKE_ROS2_DDS_H
#define FAKE_ROS2_DDS_H

#include <stdint.h>

#include <dds/dds.h>

/* A participant on @p domain, or a negative dds_return_t. */
dds_entity_t fake_dds_participant(uint32_t domain, const char *who);

#endif /* FAKE_ROS2_DDS_H */
