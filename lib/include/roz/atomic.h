/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/atomic.h
 * @brief Atomic fields in roz's public structs, for C and for C++.
 *
 * roz's structs are allocated by the application (static storage, no heap),
 * so their complete types are public, and some of their fields are atomics
 * that roz's own threads share. C++ has no `_Atomic` before C++23, so a
 * field declared `ROZ_ATOMIC(T)` is a C11 atomic in C and plain storage of
 * the same size and alignment in C++ (checked when roz is built: see
 * lib/src/atomic_check.c). Those fields are private to roz: an application,
 * in either language, reads them only through roz's functions.
 */
#ifndef ROZ_ATOMIC_H
#define ROZ_ATOMIC_H

#ifdef __cplusplus
#define ROZ_ATOMIC(T) T
#else
#include <stdatomic.h>
#define ROZ_ATOMIC(T) _Atomic T
#endif

#endif /* ROZ_ATOMIC_H */
