/* SPDX-License-Identifier: Apache-2.0 */
/* x2_stand without its balance: the same joint PD toward the same pose, no
 * IMU feedback. The baseline the balance is measured against
 * (test/ports/mujoco/test_mujoco_stand.c). */
#define STAND_BALANCE 0
#include "x2_stand.c"
