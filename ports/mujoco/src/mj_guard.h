/* SPDX-License-Identifier: Apache-2.0 */
/* The mujoco port's edge (mj_guard.cc): MuJoCo's C library throws C++
 * exceptions on some paths (std::bad_alloc, its model compiler's own) and
 * on others calls mju_user_error, whose default prints, waits for Enter
 * and exits the process. Neither leaves the port: every MuJoCo call that
 * can do either runs inside roz__mj_guard(), which turns both into an
 * error code and a message. Private to the port. */
#ifndef ROZ_PORT_MUJOCO_MJ_GUARD_H
#define ROZ_PORT_MUJOCO_MJ_GUARD_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* fn(ctx)'s result; ROZ_EIO when MuJoCo raised an error (mju_error) or
 * threw a C++ exception meanwhile, with what it said in @p what ("MuJoCo
 * error: ...", "MuJoCo ran out of memory (std::bad_alloc)", ...). fn's
 * own frames must be unwindable (the port is built with -fexceptions); no
 * heap unless MuJoCo fails (the exception's own). Context: any thread. */
int roz__mj_guard(int (*fn)(void *ctx), void *ctx, char *what, size_t len);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_MUJOCO_MJ_GUARD_H */
