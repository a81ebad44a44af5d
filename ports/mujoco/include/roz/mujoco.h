/* SPDX-License-Identifier: Apache-2.0 */
/* The old name of roz/port/mujoco.h, kept for one release. */
#include "roz/port/mujoco.h"
