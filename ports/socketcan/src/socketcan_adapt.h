/* SPDX-License-Identifier: Apache-2.0 */
/* The thin adapter between the port and Linux SocketCAN: the only file that
 * includes Linux's CAN headers is socketcan_adapt.c. Frames cross it in the
 * port's own form; errno is translated here, once. Private to the port. */
#ifndef ROZ_SOCKETCAN_ADAPT_H
#define ROZ_SOCKETCAN_ADAPT_H

#include <stddef.h>
#include <stdint.h>

#define ROZ__CAN_EFF 1u /* a 29-bit id */
#define ROZ__CAN_RTR 2u /* a remote request */
#define ROZ__CAN_ERR 4u /* an error frame: see err */

/* what an error frame reports */
#define ROZ__CAN_ERR_CRC 1u    /* a protocol violation in the CRC field */
#define ROZ__CAN_ERR_BUSOFF 2u /* the controller went bus-off */

typedef struct roz__can_frame {
    uint32_t id;      /* 11 or 29 bits */
    uint8_t  len;     /* data bytes, 0..8 */
    uint8_t  flags;   /* ROZ__CAN_* */
    uint8_t  err;     /* ROZ__CAN_ERR_* of an error frame */
    uint8_t  data[8];
} roz__can_frame_t;

/* Open a CAN_RAW socket on @p ifname with error frames enabled (bus-off,
 * protocol errors, controller problems) and own frames not looped back.
 * Returns the descriptor, or a negative ROZ_E* with @p err naming the
 * interface and the reason. */
int roz__can_open(const char *ifname, char *err, size_t errlen);

/* Wait up to @p timeout_ms for one frame. 1 read, 0 nothing yet,
 * ROZ_EIO on a socket error or end of file (a peer that closed). */
int roz__can_recv(int fd, roz__can_frame_t *out, int timeout_ms);

/* Send one frame without blocking. ROZ_OK, ROZ_ENOSPC when the socket's
 * queue is full (the bus is busy), ROZ_EIO otherwise. */
int roz__can_send(int fd, const roz__can_frame_t *f);

/* Wait up to @p timeout_ms until a frame can be sent. */
void roz__can_wait_writable(int fd, int timeout_ms);

void roz__can_close(int fd);

#endif /* ROZ_SOCKETCAN_ADAPT_H */
