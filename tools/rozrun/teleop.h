/* SPDX-License-Identifier: Apache-2.0 */
/* rozrun --teleop SOCKET: an operator's twists from another process on this
 * machine (roz-live, which takes them from Foxglove's Teleop panel;
 * docs/live.md). rozrun binds a UNIX datagram socket at SOCKET (mode 0600:
 * only its user may send) and a thread of its own takes its datagrams: each
 * one exactly ROZRUN_TELEOP_TWIST_BYTES, "TWST" then six little-endian
 * float64 (linear x, y, z, angular x, y, z), handed whole to
 * roz_runtime_operator_twist(), whose inputs' rules judge the values (a
 * non-finite one refused and counted, clamped, stale back to the default
 * at the rate cap); anything else is refused and counted. The tick never
 * waits for it. */
#ifndef ROZRUN_TELEOP_H
#define ROZRUN_TELEOP_H

#include <stdint.h>

#include "roz/atomic.h"
#include "roz/runtime.h"

#define ROZRUN_TELEOP_TWIST_BYTES (4 + 6 * 8)

typedef struct rozrun_teleop {
    const char          *path;
    int                  fd;
    int                  running;
    unsigned long        thread; /* pthread_t, kept opaque */
    roz_runtime_t       *rt;
    ROZ_ATOMIC(int)      stop;
    ROZ_ATOMIC(uint64_t) twists, refused;
} rozrun_teleop_t;

/* Binds the socket at @p path (an old socket there is replaced; any other
 * file refused). 0, or -1 with a message on stderr naming the path. */
int rozrun_teleop_open(rozrun_teleop_t *t, const char *path);

/* Starts the thread that hands each twist to @p rt. 0 or -1. */
int rozrun_teleop_start(rozrun_teleop_t *t, roz_runtime_t *rt);

/* Stops the thread (within 100 ms), closes and removes the socket. */
void rozrun_teleop_close(rozrun_teleop_t *t);

#endif /* ROZRUN_TELEOP_H */
