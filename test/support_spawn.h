/* SPDX-License-Identifier: Apache-2.0 */
/* Starting a program of this build from a test (a fake robot, rozrun, the
 * test itself as a second process): natively, or, in a cross-built tree,
 * under the emulator the test itself runs under (ROZ_TEST_EMULATOR, the
 * words of CMAKE_CROSSCOMPILING_EMULATOR as C strings, test/CMakeLists.txt),
 * since a kernel without binfmt_misc cannot start an aarch64 program on
 * x86-64. Needs _POSIX_C_SOURCE. */
#ifndef ROZ_TEST_SUPPORT_SPAWN_H
#define ROZ_TEST_SUPPORT_SPAWN_H

#include <errno.h>
#include <spawn.h>
#include <stddef.h>
#include <stdint.h>

extern char **environ;

/* posix_spawn(pid, argv[0], fa, NULL, argv, environ), argv[0] under the
 * emulator when there is one; argv is NULL-terminated, at most 32 words. */
static inline int roz_test_spawn(pid_t *pid, const posix_spawn_file_actions_t *fa,
                                 const char *const *argv)
{
#ifdef ROZ_TEST_EMULATOR
    static const char *const emu[] = { ROZ_TEST_EMULATOR, NULL };
#else
    static const char *const emu[] = { NULL };
#endif
    char *words[sizeof emu / sizeof emu[0] + 32];
    size_t n = 0;
    for (const char *const *e = emu; *e != NULL; e++)
        words[n++] = (char *)(uintptr_t)*e;
    for (size_t i = 0; argv[i] != NULL; i++) {
        if (i >= 32)
            return E2BIG;
        words[n++] = (char *)(uintptr_t)argv[i];
    }
    words[n] = NULL;
    return posix_spawn(pid, words[0], fa, NULL, words, environ);
}

#endif
