/* SPDX-License-Identifier: Apache-2.0 */
/* The old name of roz/port/mit_codec.h, kept for one release. */
#include "roz/port/mit_codec.h"
