/* SPDX-License-Identifier: Apache-2.0 */
/* roz/atomic.h lets C++ see a ROZ_ATOMIC(T) field as a plain T: that is
 * only sound where an atomic T has the size and alignment of T, and is
 * lock-free (no hidden lock word). Every type roz's public structs use is
 * checked here, at build time. */
#include "roz/atomic.h"

#include <stdint.h>

#define ROZ_SAME_AS_PLAIN(T)                                                              \
    _Static_assert(sizeof(_Atomic T) == sizeof(T) && _Alignof(_Atomic T) == _Alignof(T), \
                   "an atomic " #T " differs from a plain " #T ": C++ would see another layout")

ROZ_SAME_AS_PLAIN(int);
ROZ_SAME_AS_PLAIN(unsigned);
ROZ_SAME_AS_PLAIN(uint_fast32_t);
ROZ_SAME_AS_PLAIN(unsigned char);

_Static_assert(ATOMIC_INT_LOCK_FREE == 2,
               "roz needs lock-free atomic int (ARMv6-M, Cortex-M0/M0+, has none: "
               "see lib/CMakeLists.txt)");
