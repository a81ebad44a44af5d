/* SPDX-License-Identifier: Apache-2.0 */
/* The Linux side of the socketcan port: CAN_RAW sockets, struct can_frame,
 * error frames, errno. The only file of roz that includes <linux/can.h>. */
#define _DEFAULT_SOURCE /* struct ifreq, if_nametoindex */
#include "socketcan_adapt.h"

#include <errno.h>
#include <net/if.h>
#include <poll.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>

#include "roz/error.h"

_Static_assert(sizeof(struct can_frame) == 16, "classic CAN frames are 16 bytes on the socket");

static int from_errno(int e)
{
    switch (e) {
    case ENOBUFS:
    case EAGAIN:
        return ROZ_ENOSPC;
    case ENODEV:
    case ENXIO:
        return ROZ_ENOENT;
    default:
        return ROZ_EIO;
    }
}

int roz__can_open(const char *ifname, char *err, size_t errlen)
{
    struct sockaddr_can addr;
    can_err_mask_t mask = CAN_ERR_BUSOFF | CAN_ERR_PROT | CAN_ERR_CRTL | CAN_ERR_ACK |
                          CAN_ERR_RESTARTED;
    int off = 0;
    unsigned idx = if_nametoindex(ifname);

    if (idx == 0) {
        int e = errno;
        snprintf(err, errlen, "network_interface \"%s\": no such interface (%s)", ifname,
                 strerror(e));
        return ROZ_ENOENT;
    }
    int fd = socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (fd < 0) {
        int e = errno;
        snprintf(err, errlen, "network_interface \"%s\": cannot open a CAN_RAW socket (%s)",
                 ifname, strerror(e));
        return from_errno(e);
    }
    (void)setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &mask, sizeof mask);
    (void)setsockopt(fd, SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, &off, sizeof off);
    memset(&addr, 0, sizeof addr);
    addr.can_family = AF_CAN;
    addr.can_ifindex = (int)idx;
    if (bind(fd, (struct sockaddr *)&addr, sizeof addr) != 0) {
        int e = errno;
        snprintf(err, errlen, "network_interface \"%s\": cannot bind (%s; is it a CAN "
                 "interface, and up?)", ifname, strerror(e));
        close(fd);
        return from_errno(e);
    }
    return fd;
}

int roz__can_recv(int fd, roz__can_frame_t *out, int timeout_ms)
{
    struct pollfd p = { fd, POLLIN, 0 };
    struct can_frame f;

    int n = poll(&p, 1, timeout_ms);
    if (n == 0 || (n < 0 && errno == EINTR))
        return 0;
    if (n < 0)
        return ROZ_EIO;
    ssize_t got = read(fd, &f, sizeof f);
    if (got < 0)
        return errno == EAGAIN || errno == EINTR ? 0 : ROZ_EIO;
    if (got == 0)
        return ROZ_EIO; /* the other end closed */
    memset(out, 0, sizeof *out);
    if ((size_t)got != sizeof f) {
        out->len = 0xFF; /* not a classic CAN frame: the caller counts it */
        return 1;
    }
    out->len = f.can_dlc <= 8 ? f.can_dlc : 8;
    memcpy(out->data, f.data, out->len);
    if (f.can_id & CAN_ERR_FLAG) {
        out->flags = ROZ__CAN_ERR;
        out->id = f.can_id & CAN_ERR_MASK;
        if ((f.can_id & CAN_ERR_PROT) &&
            (f.data[3] == CAN_ERR_PROT_LOC_CRC_SEQ || f.data[3] == CAN_ERR_PROT_LOC_CRC_DEL))
            out->err |= ROZ__CAN_ERR_CRC;
        if (f.can_id & CAN_ERR_BUSOFF)
            out->err |= ROZ__CAN_ERR_BUSOFF;
        return 1;
    }
    if (f.can_id & CAN_EFF_FLAG) {
        out->flags |= ROZ__CAN_EFF;
        out->id = f.can_id & CAN_EFF_MASK;
    } else {
        out->id = f.can_id & CAN_SFF_MASK;
    }
    if (f.can_id & CAN_RTR_FLAG)
        out->flags |= ROZ__CAN_RTR;
    return 1;
}

int roz__can_send(int fd, const roz__can_frame_t *in)
{
    struct can_frame f;
    memset(&f, 0, sizeof f);
    f.can_id = in->id & CAN_SFF_MASK;
    f.can_dlc = in->len;
    memcpy(f.data, in->data, in->len);
    ssize_t n = send(fd, &f, sizeof f, MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n == (ssize_t)sizeof f)
        return 0;
    return n < 0 ? from_errno(errno) : ROZ_EIO;
}

void roz__can_wait_writable(int fd, int timeout_ms)
{
    struct pollfd p = { fd, POLLOUT, 0 };
    (void)poll(&p, 1, timeout_ms);
}

void roz__can_close(int fd)
{
    if (fd >= 0)
        close(fd);
}
