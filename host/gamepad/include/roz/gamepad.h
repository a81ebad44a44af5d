/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/gamepad.h
 * @brief A Linux gamepad (the kernel's evdev interface, /dev/input/eventN)
 *        as the operator's remote (roz/operator.h), for the simulators.
 *
 * The kernel's standard gamepad codes map onto the remote's fields by
 * position, as on Unitree's remote (an Xbox layout):
 *  - sticks ABS_X, ABS_Y -> lx, ly; ABS_RX, ABS_RY -> rx, ry; each
 *    normalised by the device's absinfo to -1..1 (centre 0, within the
 *    reported flat 0), the y axes negated (evdev's y grows downwards, the
 *    remote's upwards);
 *  - triggers ABS_Z, ABS_RZ -> l2, r2, normalised to 0..1; beyond half
 *    travel each also presses the l2 / r2 button (a pad whose triggers are
 *    axes only still gives Unitree's L2 + B);
 *  - BTN_SOUTH a, BTN_EAST b, BTN_WEST x, BTN_NORTH y; BTN_TL l1, BTN_TR
 *    r1, BTN_TL2 l2, BTN_TR2 r2; BTN_SELECT select, BTN_START start;
 *    BTN_THUMBL f1, BTN_THUMBR f2; the hat (ABS_HAT0X/Y) and
 *    BTN_DPAD_* -> up, down, left, right.
 * A frame is complete at each SYN_REPORT; after a SYN_DROPPED the events up
 * to the next SYN_REPORT are discarded and the state read again from the
 * device (or, where it cannot be, every control released and centred).
 *
 * A reader thread (roz_gamepad_start()) hands each frame to an operator
 * sink, and the last frame again whenever the device has been quiet for
 * ROZ_GAMEPAD_REPEAT_MS (evdev reports changes only: a stick held still
 * must not go stale). When the device goes away (unplugged, end of
 * file) the thread stops handing frames, and the inputs go stale.
 *
 * Host code (Linux; threads, file descriptors), never in a firmware image.
 */
#ifndef ROZ_GAMEPAD_H
#define ROZ_GAMEPAD_H

#include <pthread.h>
#include <stddef.h>
#include <stdint.h>

#include <linux/input.h>

#include "roz/atomic.h"
#include "roz/operator.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Axes read: ABS_X, ABS_Y, ABS_RX, ABS_RY, ABS_Z, ABS_RZ, in that order. */
#define ROZ_GAMEPAD_AXES 6
/** A quiet device's frame is handed on again after this long. */
#define ROZ_GAMEPAD_REPEAT_MS 20

/** One gamepad: its axes' ranges, its state and the reader thread. */
typedef struct roz_gamepad {
    struct input_absinfo abs[ROZ_GAMEPAD_AXES]; /**< each axis's range; max <= min: absent */
    int32_t  raw[ROZ_GAMEPAD_AXES];             /**< the axes' last values */
    int      hat_x, hat_y;                      /**< -1, 0, 1 */
    uint16_t keys;                              /**< buttons held (ROZ_REMOTE_KEY bits) */
    int      dropped;                           /**< after SYN_DROPPED, until SYN_REPORT */
    roz_operator_remote_t frame;                /**< the last complete frame */
    int      have_frame;
    /* the reader */
    int                 fd, wake[2], running;
    pthread_t           thread;
    roz_operator_sink_t sink;
    ROZ_ATOMIC(uint64_t) frames, repeats, drops;
    ROZ_ATOMIC(int)     gone; /**< errno of the read that ended it, or -1 at end of file */
} roz_gamepad_t;

/**
 * @brief Set up @p gp for a device whose axes are @p abs (ABS_X, ABS_Y,
 *        ABS_RX, ABS_RY, ABS_Z, ABS_RZ; an entry with max <= min is an axis
 *        the device lacks), every control released and centred.
 */
void roz_gamepad_init(roz_gamepad_t *gp, const struct input_absinfo abs[ROZ_GAMEPAD_AXES]);

/**
 * @brief One event. Returns 1 when it completed a frame (SYN_REPORT; the
 *        frame is in gp->frame), else 0. Context: the reader's thread.
 */
int roz_gamepad_event(roz_gamepad_t *gp, const struct input_event *ev);

/**
 * @brief Open the evdev device at @p path and read its axes' ranges
 *        (EVIOCGABS); a file that is no evdev device, or a device with
 *        neither sticks nor gamepad buttons, is refused, named in @p err.
 * @retval 0, or -1 with the reason in @p err
 */
int roz_gamepad_open(roz_gamepad_t *gp, const char *path, char *err, size_t errlen);

/**
 * @brief Take @p fd (any readable file of struct input_event records: a
 *        device, a pipe, a socket) with the axes' ranges @p abs; @p gp owns
 *        the descriptor from now on.
 */
void roz_gamepad_open_fd(roz_gamepad_t *gp, int fd, const struct input_absinfo abs[ROZ_GAMEPAD_AXES]);

/**
 * @brief Start the reader thread, handing frames to @p sink (a copy is
 *        kept; its remote function is called from that thread).
 * @retval 0, or -1 (no thread, no pipe) with the reason in @p err
 */
int roz_gamepad_start(roz_gamepad_t *gp, const roz_operator_sink_t *sink, char *err, size_t errlen);

/** @brief Stop the reader thread (if any) and close the device. Idempotent. */
void roz_gamepad_close(roz_gamepad_t *gp);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_GAMEPAD_H */
