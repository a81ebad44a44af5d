/* SPDX-License-Identifier: Apache-2.0 */
/* How much a long test thins its dense sweeps and random runs.
 *
 * A tree whose tests run under an emulator (test/aarch64's cross tree, under
 * qemu-aarch64) compiles its tests with ROZ_TEST_EMULATOR (test/CMakeLists.txt),
 * and there every instruction costs ten to fifty host ones (and the long
 * double the math tests take as exact is software on aarch64). There
 * ROZ_TEST_THIN(k) is k: a test takes every k-th step of a sweep, or k times
 * fewer random cases from the same seed; the tables of special and edge
 * cases always run whole. Everywhere else (the host's normal and sanitizer
 * builds, firmware) it is 1, so the counts are exactly the full ones. The counts a test prints (its seeds,
 * modules, ticks) show which it ran. */
#ifndef ROZ_TEST_SUPPORT_THIN_H
#define ROZ_TEST_SUPPORT_THIN_H

#ifdef ROZ_TEST_EMULATOR
#define ROZ_TEST_THIN(k) (k)
#else
#define ROZ_TEST_THIN(k) 1
#endif

#endif
