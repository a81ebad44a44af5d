/* SPDX-License-Identifier: Apache-2.0 */
/* The C structs idlc generates from idl/unitree_hg.idl must have the G1's
 * native layout (natural alignment), because the CRC covers the native
 * struct, padding included: checked here at build time, against the sizes
 * and offsets of the Unitree SDK's own structs. */
#include <stddef.h>

#include "unitree_hg.h"

#define LAYOUT(type, member, off) \
    _Static_assert(offsetof(type, member) == (off), #type "." #member " must be at " #off)

typedef unitree_hg_msg_dds__MotorCmd_ g1_motor_cmd_t;
typedef unitree_hg_msg_dds__MotorState_ g1_motor_state_t;
typedef unitree_hg_msg_dds__IMUState_ g1_imu_t;
typedef unitree_hg_msg_dds__LowCmd_ g1_low_cmd_t;
typedef unitree_hg_msg_dds__LowState_ g1_low_state_t;

_Static_assert(sizeof(g1_motor_cmd_t) == 28, "MotorCmd_ is 28 bytes");
LAYOUT(g1_motor_cmd_t, mode, 0);
LAYOUT(g1_motor_cmd_t, q, 4);
LAYOUT(g1_motor_cmd_t, dq, 8);
LAYOUT(g1_motor_cmd_t, tau, 12);
LAYOUT(g1_motor_cmd_t, kp, 16);
LAYOUT(g1_motor_cmd_t, kd, 20);
LAYOUT(g1_motor_cmd_t, reserve, 24);

_Static_assert(sizeof(g1_low_cmd_t) == 1004, "LowCmd_ is 1004 bytes");
LAYOUT(g1_low_cmd_t, mode_pr, 0);
LAYOUT(g1_low_cmd_t, mode_machine, 1);
LAYOUT(g1_low_cmd_t, motor_cmd, 4);
LAYOUT(g1_low_cmd_t, reserve, 984);
LAYOUT(g1_low_cmd_t, crc, 1000);

_Static_assert(sizeof(g1_imu_t) == 56, "IMUState_ is 56 bytes");
LAYOUT(g1_imu_t, quaternion, 0);
LAYOUT(g1_imu_t, gyroscope, 16);
LAYOUT(g1_imu_t, accelerometer, 28);
LAYOUT(g1_imu_t, rpy, 40);
LAYOUT(g1_imu_t, temperature, 52);

_Static_assert(sizeof(g1_motor_state_t) == 56, "MotorState_ is 56 bytes");
LAYOUT(g1_motor_state_t, mode, 0);
LAYOUT(g1_motor_state_t, q, 4);
LAYOUT(g1_motor_state_t, dq, 8);
LAYOUT(g1_motor_state_t, ddq, 12);
LAYOUT(g1_motor_state_t, tau_est, 16);
LAYOUT(g1_motor_state_t, temperature, 20);
LAYOUT(g1_motor_state_t, vol, 24);
LAYOUT(g1_motor_state_t, sensor, 28);
LAYOUT(g1_motor_state_t, motorstate, 36);
LAYOUT(g1_motor_state_t, reserve, 40);

_Static_assert(sizeof(g1_low_state_t) == 2092, "LowState_ is 2092 bytes");
LAYOUT(g1_low_state_t, version, 0);
LAYOUT(g1_low_state_t, mode_pr, 8);
LAYOUT(g1_low_state_t, mode_machine, 9);
LAYOUT(g1_low_state_t, tick, 12);
LAYOUT(g1_low_state_t, imu_state, 16);
LAYOUT(g1_low_state_t, motor_state, 72);
LAYOUT(g1_low_state_t, wireless_remote, 2032);
LAYOUT(g1_low_state_t, reserve, 2072);
LAYOUT(g1_low_state_t, crc, 2088);

/* The CRC covers every 32-bit word but the last (the crc itself). */
_Static_assert(sizeof(g1_low_cmd_t) % 4 == 0 && sizeof(g1_low_state_t) % 4 == 0,
               "the CRC reads whole words");
