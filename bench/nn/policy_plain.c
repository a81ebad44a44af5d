/* SPDX-License-Identifier: Apache-2.0 */
/* The same policy as plain wasm: roz_nn.h's C loops compiled into the
 * module instead of the nn imports (what a policy cost before them). */
#define ROZ_NN_NO_IMPORTS 1
#include "policy.c"
