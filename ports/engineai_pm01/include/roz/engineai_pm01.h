/* SPDX-License-Identifier: Apache-2.0 */
/* The old name of roz/port/engineai_pm01.h, kept for one release. */
#include "roz/port/engineai_pm01.h"
