/* SPDX-License-Identifier: Apache-2.0 */
/* A second build of g1_12dof_stand: the same controller, declaring the fuel
 * it needs (another module, another hash), as a rebuilt policy is. The one
 * a swap mid-stand hands over to (test_mujoco_stages). */
#include "g1_12dof_stand.c"

ROZ_FUEL_PER_TICK(30000);
