/* SPDX-License-Identifier: Apache-2.0 */
/* The fake G1's frames: the native layout its CRC covers (checked here at
 * compile time against the robot's), a state frame made from the robot's
 * model, and the robot's check of a received command.
 *
 * Context: any thread; the functions touch only their arguments. */
#ifndef FAKE_G1_FRAME_H
#define FAKE_G1_FRAME_H

#include <stddef.h>
#include <stdint.h>

#include "unitree_hg.h" /* idlc's output of this folder's unitree_hg.idl */

typedef unitree_hg_msg_dds__LowCmd_ g1_lowcmd_t;
typedef unitree_hg_msg_dds__LowState_ g1_lowstate_t;
typedef unitree_hg_msg_dds__MotorCmd_ g1_motorcmd_t;
typedef unitree_hg_msg_dds__MotorState_ g1_motorstate_t;
typedef unitree_hg_msg_dds__IMUState_ g1_imustate_t;

#define G1_MOTORS 35u

/* The CRC reads the native struct as the robot lays it out (natural
 * alignment, little-endian words); a different layout would be a different
 * CRC, so the build stops on one. */
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the G1's CRC is defined over little-endian words"
#endif
_Static_assert(sizeof(g1_motorcmd_t) == 28, "MotorCmd_ is 28 bytes");
_Static_assert(offsetof(g1_motorcmd_t, mode) == 0 && offsetof(g1_motorcmd_t, q) == 4 &&
                   offsetof(g1_motorcmd_t, dq) == 8 && offsetof(g1_motorcmd_t, tau) == 12 &&
                   offsetof(g1_motorcmd_t, kp) == 16 && offsetof(g1_motorcmd_t, kd) == 20 &&
                   offsetof(g1_motorcmd_t, reserve) == 24,
               "MotorCmd_ offsets");
_Static_assert(sizeof(g1_lowcmd_t) == 1004, "LowCmd_ is 1004 bytes");
_Static_assert(offsetof(g1_lowcmd_t, mode_pr) == 0 && offsetof(g1_lowcmd_t, mode_machine) == 1 &&
                   offsetof(g1_lowcmd_t, motor_cmd) == 4 && offsetof(g1_lowcmd_t, reserve) == 984 &&
                   offsetof(g1_lowcmd_t, crc) == 1000,
               "LowCmd_ offsets");
_Static_assert(sizeof(g1_imustate_t) == 56, "IMUState_ is 56 bytes");
_Static_assert(offsetof(g1_imustate_t, quaternion) == 0 &&
                   offsetof(g1_imustate_t, gyroscope) == 16 &&
                   offsetof(g1_imustate_t, accelerometer) == 28 &&
                   offsetof(g1_imustate_t, rpy) == 40 && offsetof(g1_imustate_t, temperature) == 52,
               "IMUState_ offsets");
_Static_assert(sizeof(g1_motorstate_t) == 56, "MotorState_ is 56 bytes");
_Static_assert(offsetof(g1_motorstate_t, mode) == 0 && offsetof(g1_motorstate_t, q) == 4 &&
                   offsetof(g1_motorstate_t, dq) == 8 && offsetof(g1_motorstate_t, ddq) == 12 &&
                   offsetof(g1_motorstate_t, tau_est) == 16 &&
                   offsetof(g1_motorstate_t, temperature) == 20 &&
                   offsetof(g1_motorstate_t, vol) == 24 && offsetof(g1_motorstate_t, sensor) == 28 &&
                   offsetof(g1_motorstate_t, motorstate) == 36 &&
                   offsetof(g1_motorstate_t, reserve) == 40,
               "MotorState_ offsets");
_Static_assert(sizeof(g1_lowstate_t) == 2092, "LowState_ is 2092 bytes");
_Static_assert(offsetof(g1_lowstate_t, version) == 0 && offsetof(g1_lowstate_t, mode_pr) == 8 &&
                   offsetof(g1_lowstate_t, mode_machine) == 9 &&
                   offsetof(g1_lowstate_t, tick) == 12 && offsetof(g1_lowstate_t, imu_state) == 16 &&
                   offsetof(g1_lowstate_t, motor_state) == 72 &&
                   offsetof(g1_lowstate_t, wireless_remote) == 2032 &&
                   offsetof(g1_lowstate_t, reserve) == 2072 && offsetof(g1_lowstate_t, crc) == 2088,
               "LowState_ offsets");
_Static_assert(sizeof(((g1_lowcmd_t *)0)->motor_cmd) / sizeof(g1_motorcmd_t) == G1_MOTORS &&
                   sizeof(((g1_lowstate_t *)0)->motor_state) / sizeof(g1_motorstate_t) == G1_MOTORS,
               "35 motor slots");

/* Words under each CRC: every word but the trailing crc (250 and 522). */
#define G1_LOWCMD_CRC_WORDS (sizeof(g1_lowcmd_t) / 4 - 1)
#define G1_LOWSTATE_CRC_WORDS (sizeof(g1_lowstate_t) / 4 - 1)

/* CRCs of the native images (padding included, as it lies in memory). */
uint32_t g1_lowcmd_crc(const g1_lowcmd_t *c);
uint32_t g1_lowstate_crc(const g1_lowstate_t *s);

/* Copy @p src into @p dst member by member over a zeroed @p dst, so that
 * the padding under the CRC is zero whatever @p src's padding holds: what
 * a receiver rebuilds from the wire, which carries no padding. */
void g1_lowcmd_copy(g1_lowcmd_t *dst, const g1_lowcmd_t *src);
void g1_lowstate_copy(g1_lowstate_t *dst, const g1_lowstate_t *src);

/* A state frame: @p model's values with @p tick, over a zeroed frame, its
 * CRC set. */
void g1_state_frame(g1_lowstate_t *frame, const g1_lowstate_t *model, uint32_t tick);

/* The robot's check of a received command: its CRC recomputed over a
 * freshly zeroed struct filled from @p received. 1 if it matches. */
int g1_lowcmd_crc_ok(const g1_lowcmd_t *received);

#endif /* FAKE_G1_FRAME_H */
