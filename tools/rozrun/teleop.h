/* SPDX-License-Identifier: Apache-2.0 */
/* rozrun --teleop SOCKET: an operator's twists and joysticks from another
 * process on this machine (roz-live, which takes them from Foxglove's Teleop
 * and Joystick panels; docs/live.md). rozrun binds a UNIX datagram socket at
 * SOCKET (mode 0600: only its user may send) and a thread of its own takes
 * its datagrams:
 *  - a twist: exactly ROZRUN_TELEOP_TWIST_BYTES, "TWST" then six
 *    little-endian float64 (linear x, y, z, angular x, y, z), handed whole
 *    to roz_runtime_operator_twist();
 *  - a joystick (sensor_msgs/Joy): "JOY1", the number of axes and of
 *    buttons (a byte each, at most ROZ_JOY_MAX), the length of a map's text
 *    (little-endian uint16, at most ROZRUN_TELEOP_JOY_MAP_MAX; 0: none),
 *    the axes as little-endian float32, the buttons as little-endian int32,
 *    then the map's text (roz-live --joy-map: the roz/joy.h grammar, no
 *    NUL), nothing more; mapped onto the remote by its map, or without one
 *    by ROZRUN_TELEOP_JOY_MAP, with the core's Joy rule, the ROS 2 ports'
 *    joy_map's too (roz/joy.h: a Joy lacking a mapped axis or button, or
 *    with a mapped axis not finite, is refused whole; so is every Joy whose
 *    map the rule refuses, said once on stderr) and handed to
 *    roz_runtime_operator_remote() (the remote's e-stop chord included).
 *    A map is read once and kept while the next Joys carry the same text.
 *    Every build takes them: the rule needs no ROS 2 port nor DDS.
 * The inputs' rules judge the values (a non-finite one refused and counted,
 * clamped, stale back to the default at the rate cap); anything else is
 * refused and counted. The tick never waits for it. */
#ifndef ROZRUN_TELEOP_H
#define ROZRUN_TELEOP_H

#include <stdint.h>

#include "roz/atomic.h"
#include "roz/joy.h"
#include "roz/runtime.h"

#define ROZRUN_TELEOP_TWIST_BYTES (4 + 6 * 8)
#define ROZRUN_TELEOP_JOY_MAX ROZ_JOY_MAX /* axes, and buttons, at most */
#define ROZRUN_TELEOP_JOY_MAP_MAX 512 /* a Joy's map's text, bytes at most */
#define ROZRUN_TELEOP_JOY_BYTES_MAX (8 + ROZRUN_TELEOP_JOY_MAX * 8 + ROZRUN_TELEOP_JOY_MAP_MAX)

/* Foxglove's Joystick panel (a gamepad through the browser's Gamepad API, its
 * "standard" layout, every axis negated as the panel publishes it) onto the
 * remote, for a Joy that carries no map (roz-live without --joy-map): axes left x, left y, right x, right y with left and up positive;
 * buttons A 0, B 1, X 2, Y 3, the shoulders 4 and 5, the triggers 6 and 7 (0
 * or 1), back 8, start 9, the sticks 10 and 11, the D-pad up 12, down 13,
 * left 14, right 15. */
#define ROZRUN_TELEOP_JOY_MAP                                                                 \
    "lx=-a0 ly=a1 rx=-a2 ry=a3 l2=b6 r2=b7 btn.r1=b5 btn.l1=b4 btn.start=b9 btn.select=b8 "   \
    "btn.r2=b7 btn.l2=b6 btn.a=b0 btn.b=b1 btn.x=b2 btn.y=b3 btn.up=b12 btn.right=b15 "        \
    "btn.down=b13 btn.left=b14"

typedef struct rozrun_teleop {
    const char          *path;
    int                  fd;
    int                  running;
    unsigned long        thread; /* pthread_t, kept opaque */
    roz_runtime_t       *rt;
    ROZ_ATOMIC(int)      stop;
    ROZ_ATOMIC(uint64_t) twists, joys, refused;
    roz_joy_map_t        joy_map; /* ROZRUN_TELEOP_JOY_MAP, read at open */
    /* the teleop thread's: the last map a Joy carried, its text and rule */
    roz_joy_map_t        sent_map;
    char                 sent_text[ROZRUN_TELEOP_JOY_MAP_MAX + 1];
    size_t               sent_len; /* 0: none yet */
    int                  sent_ok;
} rozrun_teleop_t;

/* Binds the socket at @p path (an old socket there is replaced; any other
 * file refused). 0, or -1 with a message on stderr naming the path. */
int rozrun_teleop_open(rozrun_teleop_t *t, const char *path);

/* Starts the thread that hands each twist to @p rt. 0 or -1. */
int rozrun_teleop_start(rozrun_teleop_t *t, roz_runtime_t *rt);

/* Stops the thread (within 100 ms), closes and removes the socket. */
void rozrun_teleop_close(rozrun_teleop_t *t);

#endif /* ROZRUN_TELEOP_H */
