/* SPDX-License-Identifier: Apache-2.0 */
/* Private to roz::dds: Cyclone's return codes and QoS, translated once. */
#ifndef ROZ_DDS_INTERNAL_H
#define ROZ_DDS_INTERNAL_H

#include <stddef.h>

#include <dds/dds.h>

#include "roz/port/dds.h"

/* A Cyclone return code as a roz code. */
int roz__dds_error(dds_return_t rc);

/* "topic rt/lowcmd: <what>: <Cyclone's message>" into err. */
void roz__dds_say(char *err, size_t errlen, const char *topic, const char *what, dds_return_t rc);

/* A new dds_qos_t for a profile (dds_delete_qos() it). NULL: out of memory. */
dds_qos_t *roz__dds_qos(const roz_dds_qos_t *q);

#endif /* ROZ_DDS_INTERNAL_H */
