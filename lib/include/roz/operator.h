/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/operator.h
 * @brief Operator devices: the fields an operator input can take its value
 *        from (robot.toml's `source` on a [[manifest.inputs]] entry), and
 *        the calls a device's reader makes with a whole frame.
 *
 * Two devices, a fixed vocabulary:
 *  - the remote, shaped as Unitree's wireless remote (the G1's
 *    LowState_.wireless_remote; a Linux gamepad mapped onto it): sticks
 *    `remote.lx`, `remote.ly`, `remote.rx`, `remote.ry` (-1..1), analog
 *    triggers `remote.l2`, `remote.r2` (0..1) and sixteen buttons
 *    `remote.btn.<name>` (0 or 1) in the bit order of Unitree's SDK's key
 *    union: r1 (bit 0), l1, start, select, r2, l2, f1, f2, a, b, x, y,
 *    up, right, down, left (bit 15);
 *  - a twist (geometry_msgs/Twist: ROS 2 /cmd_vel, Foxglove's teleop):
 *    `twist.linear.x|y|z`, `twist.angular.x|y|z`.
 *
 * An input with a source takes scale * the field each time its device
 * delivers a frame, then the input's own rules (roz/inputs.h: non-finite
 * refused, clamped, stale back to its default, every change rate capped).
 * One field feeds at most one input (the manifest's rule).
 */
#ifndef ROZ_OPERATOR_H
#define ROZ_OPERATOR_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** A field of an operator device; ROZ_OPERATOR_NONE: the input has no
 *  source (only the API and the scripted operator set it). */
typedef enum roz_operator_field {
    ROZ_OPERATOR_NONE = 0,
    ROZ_OPERATOR_REMOTE_LX, /**< "remote.lx": left stick, right positive, -1..1 */
    ROZ_OPERATOR_REMOTE_LY, /**< "remote.ly": left stick, up positive */
    ROZ_OPERATOR_REMOTE_RX, /**< "remote.rx" */
    ROZ_OPERATOR_REMOTE_RY, /**< "remote.ry" */
    ROZ_OPERATOR_REMOTE_L2, /**< "remote.l2": left trigger, 0..1 */
    ROZ_OPERATOR_REMOTE_R2, /**< "remote.r2": right trigger, 0..1 */
    ROZ_OPERATOR_REMOTE_BTN_R1, /**< "remote.btn.r1": bit 0 of the buttons; the
                                     others follow in bit order */
    ROZ_OPERATOR_REMOTE_BTN_L1,
    ROZ_OPERATOR_REMOTE_BTN_START,
    ROZ_OPERATOR_REMOTE_BTN_SELECT,
    ROZ_OPERATOR_REMOTE_BTN_R2,
    ROZ_OPERATOR_REMOTE_BTN_L2,
    ROZ_OPERATOR_REMOTE_BTN_F1,
    ROZ_OPERATOR_REMOTE_BTN_F2,
    ROZ_OPERATOR_REMOTE_BTN_A,
    ROZ_OPERATOR_REMOTE_BTN_B,
    ROZ_OPERATOR_REMOTE_BTN_X,
    ROZ_OPERATOR_REMOTE_BTN_Y,
    ROZ_OPERATOR_REMOTE_BTN_UP,
    ROZ_OPERATOR_REMOTE_BTN_RIGHT,
    ROZ_OPERATOR_REMOTE_BTN_DOWN,
    ROZ_OPERATOR_REMOTE_BTN_LEFT, /**< "remote.btn.left": bit 15 */
    ROZ_OPERATOR_TWIST_LINEAR_X,  /**< "twist.linear.x" */
    ROZ_OPERATOR_TWIST_LINEAR_Y,
    ROZ_OPERATOR_TWIST_LINEAR_Z,
    ROZ_OPERATOR_TWIST_ANGULAR_X,
    ROZ_OPERATOR_TWIST_ANGULAR_Y,
    ROZ_OPERATOR_TWIST_ANGULAR_Z, /**< "twist.angular.z" */
    ROZ_OPERATOR_FIELD_COUNT_     /**< number of fields; not a field */
} roz_operator_field_t;

/** The bit of a remote button in roz_operator_remote_t.buttons (Unitree's
 *  key union): ROZ_REMOTE_KEY(ROZ_OPERATOR_REMOTE_BTN_A) == 1u << 8. */
#define ROZ_REMOTE_KEY(field) ((uint16_t)(1u << ((unsigned)(field) - ROZ_OPERATOR_REMOTE_BTN_R1)))

/** One frame of the remote. */
typedef struct roz_operator_remote {
    float    lx, ly, rx, ry; /**< sticks, -1..1 */
    float    l2, r2;         /**< triggers, 0..1 */
    uint16_t buttons;        /**< bit i: button i of the key union (ROZ_REMOTE_KEY) */
} roz_operator_remote_t;

/** One frame of a twist (geometry_msgs/Twist). */
typedef struct roz_operator_twist {
    double linear[3];  /**< x, y, z */
    double angular[3]; /**< x, y, z */
} roz_operator_twist_t;

/** Which device a field belongs to. */
typedef enum roz_operator_device {
    ROZ_OPERATOR_DEVICE_NONE = 0,
    ROZ_OPERATOR_DEVICE_REMOTE,
    ROZ_OPERATOR_DEVICE_TWIST,
} roz_operator_device_t;

/**
 * @brief The name of a field as written in robot.toml ("remote.ly").
 * @return the name; "" for ROZ_OPERATOR_NONE; "?" outside the enum.
 * Context: any; RT-safe.
 */
const char *roz_operator_field_name(roz_operator_field_t f);

/**
 * @brief Parse a field name of @p len bytes (not NUL-terminated).
 * @retval ROZ_OK     *f set
 * @retval ROZ_EINVAL not a field of the vocabulary (or a NULL argument)
 * Context: any; RT-safe; O(fields).
 */
int roz_operator_field_parse(const char *name, size_t len, roz_operator_field_t *f);

/** @brief The device of @p f (ROZ_OPERATOR_DEVICE_NONE for NONE or a value
 *  outside the enum). Context: any; RT-safe. */
roz_operator_device_t roz_operator_field_device(roz_operator_field_t f);

/** @brief Field @p f of a remote frame, as a double (a button: 0 or 1);
 *  0 for a field of another device. Context: any; RT-safe. */
double roz_operator_remote_field(const roz_operator_remote_t *r, roz_operator_field_t f);

/** @brief Field @p f of a twist frame; 0 for a field of another device.
 *  Context: any; RT-safe. */
double roz_operator_twist_field(const roz_operator_twist_t *t, roz_operator_field_t f);

/**
 * Where a device's reader (a port's receive thread, a gamepad reader)
 * hands its frames: roz_runtime_operator_sink() makes one for a runtime; a
 * port takes one before it is activated (roz_port_set_operator()). Each
 * function is called from the reader's thread and must be wait-free, as
 * the runtime's are. A NULL function: the device's frames go nowhere.
 */
typedef struct roz_operator_sink {
    int (*remote)(void *ctx, const roz_operator_remote_t *r);
    int (*twist)(void *ctx, const roz_operator_twist_t *t);
    void *ctx;
} roz_operator_sink_t;

struct roz_runtime;

/**
 * @brief A frame of the remote: every input whose source is a field of the
 *        remote takes scale * that field (roz_runtime_input_set()'s path:
 *        the next tick judges it). When the frame holds every button of the
 *        manifest's remote_estop, it presses the e-stop first:
 *        ROZ_FAULT_ESTOP latches at the next tick (a chord released before
 *        it still latches) and stays latched until roz_runtime_clear_faults(),
 *        which is refused (ROZ_ESTATE) while the remote's last frame held
 *        the chord; a release or a silent remote never clears it.
 * @param rt  a roz_runtime_t
 * @retval ROZ_OK     every such input stored (none is fine)
 * @retval ROZ_EINVAL a NULL argument
 * @retval ROZ_ESTATE a set of one of them was in progress and this frame's
 *                    value of it was dropped (the others are stored)
 * Context: any thread (a port's DDS callback, a gamepad reader); wait-free,
 *          O(inputs), no heap, no lock.
 */
int roz_runtime_operator_remote(struct roz_runtime *rt, const roz_operator_remote_t *r);

/** @brief As roz_runtime_operator_remote(), for a twist.
 *  Context: as roz_runtime_operator_remote(). */
int roz_runtime_operator_twist(struct roz_runtime *rt, const roz_operator_twist_t *t);

/**
 * @brief A sink whose functions are roz_runtime_operator_remote() and
 *        roz_runtime_operator_twist() on @p rt.
 * Context: start-up. The runtime must be set up (roz_runtime_init()) before
 *          any reader given the sink runs (before the port's activate, the
 *          gamepad's start) and outlive it.
 */
roz_operator_sink_t roz_runtime_operator_sink(struct roz_runtime *rt);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_OPERATOR_H */
