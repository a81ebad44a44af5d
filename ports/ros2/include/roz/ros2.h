/* SPDX-License-Identifier: Apache-2.0 */
/* The old name of roz/port/ros2.h, kept for one release. */
#include "roz/port/ros2.h"
