/* SPDX-License-Identifier: Apache-2.0 */
/* The C structs idlc generates from idl/unitree_hg.idl must have the G1's
 * native layout (natural alignment), because the CRC covers the native
 * struct, padding included: checked here at build time, against the sizes
 * and offsets of the Unitree SDK's own structs. */
#include <stddef.h>

#include "unitree_hg.h"

typedef unitree_hg_msg_dds__MotorCmd_ g1_motor_cmd_t;
typedef unitree_hg_msg_dds__MotorState_ g1_motor_state_t;
typedef unitree_hg_msg_dds__IMUState_ g1_imu_t;
typedef unitree_hg_msg_dds__LowCmd_ g1_low_cmd_t;
typedef unitree_hg_msg_dds__LowState_ g1_low_state_t;

/* The SDK's structs, a row each: the members' offsets (bytes). */
#define MOTOR_CMD(F, t)                                                                     \
    F(t, mode, 0) F(t, q, 4) F(t, dq, 8) F(t, tau, 12) F(t, kp, 16) F(t, kd, 20)          \
    F(t, reserve, 24)
#define LOW_CMD(F, t)                                                                       \
    F(t, mode_pr, 0) F(t, mode_machine, 1) F(t, motor_cmd, 4) F(t, reserve, 984)          \
    F(t, crc, 1000)
#define IMU_STATE(F, t)                                                                     \
    F(t, quaternion, 0) F(t, gyroscope, 16) F(t, accelerometer, 28) F(t, rpy, 40)         \
    F(t, temperature, 52)
#define MOTOR_STATE(F, t)                                                                   \
    F(t, mode, 0) F(t, q, 4) F(t, dq, 8) F(t, ddq, 12) F(t, tau_est, 16)                  \
    F(t, temperature, 20) F(t, vol, 24) F(t, sensor, 28) F(t, motorstate, 36)             \
    F(t, reserve, 40)
#define LOW_STATE(F, t)                                                                     \
    F(t, version, 0) F(t, mode_pr, 8) F(t, mode_machine, 9) F(t, tick, 12)                \
    F(t, imu_state, 16) F(t, motor_state, 72) F(t, wireless_remote, 2032)                 \
    F(t, reserve, 2072) F(t, crc, 2088)

#define AT(type, member, off) \
    _Static_assert(offsetof(type, member) == (off), #type "." #member " must be at " #off);
#define LAYOUT(type, size, MEMBERS)                                                         \
    _Static_assert(sizeof(type) == (size), #type " is " #size " bytes");                   \
    MEMBERS(AT, type)

LAYOUT(g1_motor_cmd_t, 28, MOTOR_CMD)
LAYOUT(g1_low_cmd_t, 1004, LOW_CMD)
LAYOUT(g1_imu_t, 56, IMU_STATE)
LAYOUT(g1_motor_state_t, 56, MOTOR_STATE)
LAYOUT(g1_low_state_t, 2092, LOW_STATE)

/* The CRC covers every 32-bit word but the last (the crc itself). */
_Static_assert(sizeof(g1_low_cmd_t) % 4 == 0 && sizeof(g1_low_state_t) % 4 == 0,
               "the CRC reads whole words");
