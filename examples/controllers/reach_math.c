/* SPDX-License-Identifier: Apache-2.0 */
/* The math of reach.zig: roz_math.h's functions, compiled by Zig's C
 * compiler into the Zig module (its functions are static inline, which Zig
 * cannot call from another file). Linked, not exported: the module exports
 * process alone. */
#include "roz_math.h"

double reach_sin(double x) { return roz_math_sin(x); }
double reach_cos(double x) { return roz_math_cos(x); }
double reach_atan2(double y, double x) { return roz_math_atan2(y, x); }
double reach_sqrt(double x) { return roz_math_sqrt(x); }
double reach_exp(double x) { return roz_math_exp(x); }
double reach_tanh(double x) { return roz_math_tanh(x); }
double reach_clamp(double x, double lo, double hi) { return roz_math_clamp(x, lo, hi); }
