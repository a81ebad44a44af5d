/* SPDX-License-Identifier: Apache-2.0 */
/* The old name of roz/port/loopback.h, kept for one release. */
#include "roz/port/loopback.h"
