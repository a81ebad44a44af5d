/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/port.h
 * @brief The port interface every hardware port implements.
 *
 * A port is a const ops table plus the port's own instance data. The core
 * calls a port only through these wrappers. Channel binding happens once in
 * open(): the port looks the manifest's channels up by name and keeps
 * indices; read() and write() move plain arrays in manifest order.
 *
 * Every hardware port keeps three layers of safe start-up: it sends nothing
 * before its first state frame; on the first state frame it sets every
 * command to the current position with zero stiffness and damping; and it
 * does the same on the first write.
 */
#ifndef ROZ_PORT_H
#define ROZ_PORT_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/error.h"
#include "roz/manifest.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Port parameters: string key/values (robot.toml [hardware.params], CLI). */
typedef struct roz_params {
    const roz_param_t *items;
    size_t             n;
} roz_params_t;

/** What the robot reported when read() returned ROZ_EROBOT. */
typedef struct roz_port_fault {
    const char *what; /**< the part at fault, in storage that lives as long as
                           the port is open: "left_knee_joint" */
    const char *kind; /**< what it reported, static: "motor fault code" */
    uint32_t    code; /**< the robot's own code; after ROZ_EWATCHDOG: how long
                           the tick wrote no command, microseconds */
    uint32_t    limit; /**< after ROZ_EWATCHDOG: the port's command timeout,
                            microseconds; 0 otherwise */
} roz_port_fault_t;

/** The operations of one kind of port. Optional ops may be NULL. */
typedef struct roz_port_ops {
    const char *name; /**< "loopback", "unitree/G1", ... */
    /** Parse parameters, allocate, bind channels by name. Errors name the
     *  parameter or channel in @p err. Context: start-up; may allocate. */
    int (*open)(void *self, const roz_manifest_t *m, const roz_params_t *p, char *err,
                size_t errlen);
    /** Start threads / transport. Optional. */
    int (*activate)(void *self);
    /** Copy the latest state (n = n_states values). Returns 1 for a fresh
     *  frame, 0 when nothing newer than the last read arrived (state then
     *  holds the previous frame), negative ROZ_E* on error (ROZ_ENOENT: no
     *  frame ever; ROZ_ELINK: the link to the robot broke, its peer restarted
     *  or came back after it was lost (roz/hal/link.h), which latches
     *  ROZ_FAULT_LINK; ROZ_EROBOT: a fresh frame, in @p state, in which the
     *  robot reports a fault of its own (fault() says which), which latches
     *  ROZ_FAULT_ROBOT; a port returns it for every fresh frame while the
     *  robot reports the fault: a level, not an event; ROZ_EWATCHDOG: the
     *  port's command watchdog (roz/hal/cmd_watchdog.h) found the tick
     *  silent for longer than its command timeout and sent the robot its
     *  safe command instead of the stale one; reported once per trip, in
     *  place of 0 or 1 (state holds the latest frame, which the runtime
     *  takes as not fresh), with fault() giving how long the tick was
     *  silent (code) and the timeout (limit); latches
     *  ROZ_FAULT_COMMAND_TIMEOUT).
     *  Context: the tick; RT-safe, never blocks. */
    int (*read)(void *self, double *state, size_t n);
    /** Hand n = n_commands filtered commands to the robot. Context: the
     *  tick; RT-safe, never blocks. */
    int (*write)(void *self, const double *cmd, size_t n);
    /** Stop threads. Optional. */
    int (*deactivate)(void *self);
    /** Free everything; idempotent. Optional. */
    void (*close)(void *self);
    /** After read() returned ROZ_EROBOT: what the robot reported; after
     *  ROZ_EWATCHDOG: the silence and the timeout. After read() returned 0
     *  (nothing fresh): why, when the port knows (an actuator that stopped
     *  answering, named), else not ROZ_OK; the runtime adds it to the STALE
     *  fault's message when that latches. Optional (without it the fault
     *  has a code of 0 and no name).
     *  Context: the tick; RT-safe. */
    int (*fault)(void *self, roz_port_fault_t *out);
} roz_port_ops_t;

/** A port instance: its ops and its data. */
typedef struct roz_port {
    const roz_port_ops_t *ops;
    void                 *self;
    /** 1 once roz_port_open() succeeded, 0 again after roz_port_close(); set
     *  only by those two. roz_runtime_init() refuses a port that is not
     *  open: its read() would run on an instance that was never set up. */
    int                   opened;
} roz_port_t;

/** @brief open(); a port without the op has nothing to open and is open at
 *  once. Marks @p p open on success. Context: start-up; may allocate. */
static inline int roz_port_open(roz_port_t *p, const roz_manifest_t *m,
                                const roz_params_t *params, char *err, size_t errlen)
{
    int rc = p->ops->open != NULL ? p->ops->open(p->self, m, params, err, errlen) : ROZ_OK;
    p->opened = rc == ROZ_OK;
    return rc;
}

/** @brief activate(); ROZ_OK when the port has none (nothing to start).
 *  Context: start-up, not the tick. */
static inline int roz_port_activate(const roz_port_t *p)
{
    return p->ops->activate != NULL ? p->ops->activate(p->self) : ROZ_OK;
}

/** @brief read()
 *  Context: the tick; must not block. */
static inline int roz_port_read(const roz_port_t *p, double *state, size_t n)
{
    return p->ops->read != NULL ? p->ops->read(p->self, state, n) : ROZ_ENOTSUP;
}

/** @brief write()
 *  Context: the tick; must not block. */
static inline int roz_port_write(const roz_port_t *p, const double *cmd, size_t n)
{
    return p->ops->write != NULL ? p->ops->write(p->self, cmd, n) : ROZ_ENOTSUP;
}

/** @brief deactivate(); ROZ_OK when the port has none.
 *  Context: shut-down, after the tick stopped. */
static inline int roz_port_deactivate(const roz_port_t *p)
{
    return p->ops->deactivate != NULL ? p->ops->deactivate(p->self) : ROZ_OK;
}

/** @brief close(), if any; marks @p p not open.
 *  Context: shut-down, after the tick stopped; idempotent. */
static inline void roz_port_close(roz_port_t *p)
{
    if (p->ops->close != NULL)
        p->ops->close(p->self);
    p->opened = 0;
}

#ifdef __cplusplus
}
#endif

#endif /* ROZ_PORT_H */
