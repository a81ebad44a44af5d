/* SPDX-License-Identifier: Apache-2.0 */
/* The old name of roz/port/dds.h, kept for one release. */
#include "roz/port/dds.h"
