/* SPDX-License-Identifier: Apache-2.0 */
/* The old name of roz/port/unitree_g1.h, kept for one release. */
#include "roz/port/unitree_g1.h"
