/* SPDX-License-Identifier: Apache-2.0 */
/* The old name of roz/port/agibot_x2.h, kept for one release. */
#include "roz/port/agibot_x2.h"
