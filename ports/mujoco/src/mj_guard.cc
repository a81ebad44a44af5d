// SPDX-License-Identifier: Apache-2.0
// The mujoco port's edge (mj_guard.h): nothing MuJoCo throws or raises
// gets past it (test_mujoco_engine_error_is_a_fault).
#include "mj_guard.h"

#include <exception>
#include <new>

#include <mujoco/mujoco.h>

#include "roz/error.h"

namespace {

// What mju_user_error said, for the catch below: copied without the heap.
thread_local char said[512];

struct engine_error {};

// MuJoCo's messages run over lines: one line, runs of blanks as one.
void copy(char *out, size_t len, size_t at, const char *text)
{
    for (; len > 0 && at + 1 < len && text != nullptr && *text != '\0'; text++) {
        char c = *text == '\n' || *text == '\t' ? ' ' : *text;
        if (c == ' ' && (at == 0 || out[at - 1] == ' '))
            continue;
        out[at++] = c;
    }
    if (len > 0)
        out[at < len ? at : len - 1] = '\0';
}

size_t length(const char *s)
{
    size_t n = 0;
    while (s[n] != '\0')
        n++;
    return n;
}

void say(char *out, size_t len, const char *head, const char *tail)
{
    if (len == 0)
        return;
    copy(out, len, 0, head);
    copy(out, len, length(out), tail);
    for (size_t at = length(out); at > 0 && out[at - 1] == ' '; at--)
        out[at - 1] = '\0';
}

// MuJoCo's error callback: it must not return (the engine goes on after
// it as if the error could not happen), so it throws to the guard.
[[noreturn]] void on_error(const char *msg)
{
    copy(said, sizeof said, 0, msg);
    throw engine_error{};
}

} // namespace

extern "C" int roz__mj_guard(int (*fn)(void *ctx), void *ctx, char *what, size_t len)
{
    mju_user_error = on_error;
    try {
        return fn(ctx);
    } catch (const engine_error &) {
        say(what, len, "MuJoCo error: ", said);
    } catch (const std::bad_alloc &) {
        say(what, len, "MuJoCo ran out of memory (std::bad_alloc)", "");
    } catch (const std::exception &e) {
        say(what, len, "MuJoCo threw a C++ exception: ", e.what());
    } catch (...) {
        say(what, len, "MuJoCo threw a C++ exception of an unknown type", "");
    }
    return ROZ_EIO;
}
