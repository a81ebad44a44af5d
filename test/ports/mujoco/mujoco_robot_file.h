/* SPDX-License-Identifier: Apache-2.0 */
/* The mujoco tests' robot.toml files (test/ports/mujoco/<file>): loaded by
 * roz's C loader into static storage, the port over @p mj told it is the
 * robot file (its model is found beside it). Fails the test with the
 * loader's first problem. */
#ifndef ROZ_TEST_MUJOCO_ROBOT_FILE_H
#define ROZ_TEST_MUJOCO_ROBOT_FILE_H

#include "roz/manifest.h"
#include "roz/port/mujoco.h"

const roz_manifest_t *roz_test_mujoco_robot_file(roz_mujoco_t *mj, const char *file);

#endif /* ROZ_TEST_MUJOCO_ROBOT_FILE_H */
