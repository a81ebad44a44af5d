/* SPDX-License-Identifier: Apache-2.0 */
/* The old name of roz/port/can_config.h, kept for one release. */
#include "roz/port/can_config.h"
