/* SPDX-License-Identifier: Apache-2.0 */
/* roz built with every part a firmware may leave out left out
 * (roz/config.h, "what a build leaves out"): test_left_out's build of the
 * core. */
#ifndef ROZ_TEST_LEFT_OUT_CONFIG_H
#define ROZ_TEST_LEFT_OUT_CONFIG_H

#define ROZ_CFG_NN_IMPORTS    0
#define ROZ_CFG_MATH_IMPORTS  0
#define ROZ_CFG_BULK_IMPORTS  0
#define ROZ_CFG_FORMAT_DOUBLE 0
#define ROZ_CFG_MAX_INPUTS    0
#define ROZ_CFG_FALL          0

#endif /* ROZ_TEST_LEFT_OUT_CONFIG_H */
