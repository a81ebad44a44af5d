/* SPDX-License-Identifier: Apache-2.0 */
/* roz_math.h needs nothing: this file is compiled with -ffreestanding
 * -nostdinc as C99, so any system header it pulled in would fail the build. */
#include "roz_math.h"

double roz_math_freestanding_use(double x, double y);

double roz_math_freestanding_use(double x, double y)
{
    return roz_math_fabs(x) + roz_math_copysign(x, y) + roz_math_sqrt(x) + roz_math_floor(x) +
           roz_math_ceil(x) + roz_math_trunc(x) + roz_math_fmin(x, y) + roz_math_fmax(x, y) +
           roz_math_clamp(x, -1.0, 1.0) + roz_math_sin(x) + roz_math_cos(x) +
           roz_math_atan2(y, x) + roz_math_exp(x) + roz_math_log(x) + roz_math_pow(x, y) +
           roz_math_tanh(x);
}
