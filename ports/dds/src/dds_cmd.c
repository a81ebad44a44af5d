/* SPDX-License-Identifier: Apache-2.0 */
/* The command path of every DDS port: the tick's write, the writer thread's
 * pass, the watchdog's report, the last command. roz/port/dds.h says what it
 * does and which thread runs what; the port's hooks put it on its wire. */
#include "roz/port/dds.h"

#include <string.h>

#include "roz/hal/clock.h"
#include "roz/hal/joints.h"

/* ---- types ----------------------------------------------------------------------- */

/* The meta words after the commands (ROZ_DDS_CMD_META); the port's follow. */
enum { C_SESSION = 0, C_HOLD, C_SEQ, C_EPOCH };

_Static_assert(C_EPOCH + 1 == ROZ_DDS_CMD_META, "command frame meta");

/* ---- private --------------------------------------------------------------------- */

static void bump(roz_dds_cmd_t *c, roz_dds_cmd_counter_t k)
{
    atomic_fetch_add_explicit(&c->count[k], 1u, memory_order_relaxed);
}

/* The watchdog's time now (roz_dds_cmd_config_t clock). */
static uint64_t clock_now(const roz_dds_cmd_t *c)
{
    return c->clock(c->clock_ctx);
}

/* The writer's pass (its thread; on deactivate, the caller's once it is
 * joined): the latest frame, the watchdog's safe command, or nothing. */
static int pass(void *ctx, void *sample, uint64_t now_ns)
{
    roz_dds_cmd_t *c = ctx;
    const roz_dds_cmd_ops_t *ops = c->ops;
    roz_buffer_frame_t f;

    (void)now_ns; /* the watchdog's own clock below: the same one where it is the monotonic */
    if (atomic_load_explicit(&c->shutdown, memory_order_acquire)) {
        /* the last command: the port's exit (safe()), if the robot ever got one */
        if (!c->sent_any)
            return 0;
        return ops->safe(c->port, sample);
    }
    if (atomic_load_explicit(&c->held_back, memory_order_acquire))
        return 0;
    if (roz_buffer_read(&c->buf, &f) == ROZ_ENOENT)
        return 0;
    const double *meta = f.values + c->m->n_commands;
    uint64_t seq = (uint64_t)meta[C_SEQ];
    int refused = ops->refuse != NULL && ops->refuse(c->port);
    int rc = 0;

    if ((uint32_t)meta[C_SESSION] != ops->rx_session(c->port)) {
        /* written for a robot that restarted since: the new one gets
         * nothing until the tick writes for it */
        bump(c, ROZ_DDS_CMD_STALE);
    } else if (refused) {
        bump(c, ROZ_DDS_CMD_REFUSED);
    } else if (roz_cmd_watchdog_judge(&c->watchdog, (uint32_t)meta[C_EPOCH], meta[C_HOLD] != 0.0,
                                      f.stamp_ns, clock_now(c)) == ROZ_CMD_SAFE) {
        /* the tick went silent (or this was written before it was found
         * so): the hold at the positions last sent, with the manifest's
         * hold gains, until it writes again (a standing humanoid given
         * the damping command falls: test/ports/mujoco/test_mujoco_stops.c);
         * nothing to a robot that never got a command */
        if (c->sent_any) {
            rc = ops->watchdog != NULL ? ops->watchdog(c->port, sample) : ops->safe(c->port, sample);
            bump(c, ROZ_DDS_CMD_SAFE);
        }
    } else {
        rc = ops->send(c->port, sample, f.values, meta + ROZ_DDS_CMD_META, meta[C_HOLD] != 0.0);
        c->sent_any = 1;
        if (meta[C_HOLD] != 0.0) /* the tick's writes are holds until then */
            atomic_store_explicit(&c->count[ROZ_DDS_CMD_HOLD_SENT_SEQ], seq,
                                  memory_order_release);
    }
    atomic_store_explicit(&c->count[ROZ_DDS_CMD_HANDLED_SEQ], seq, memory_order_release);
    return rc;
}

/* ---- public ---------------------------------------------------------------------- */

void roz_dds_cmd_init(roz_dds_cmd_t *c, const roz_dds_cmd_config_t *cfg)
{
    memset(c, 0, sizeof *c);
    c->m = cfg->m;
    c->ops = cfg->ops;
    c->port = cfg->port;
    c->writer = cfg->writer;
    c->n_extra = cfg->n_extra;
    c->timeout_us = cfg->timeout_us;
    c->clock = cfg->clock != NULL ? cfg->clock : roz_clock_monotonic_ns;
    c->clock_ctx = cfg->clock_ctx;
    roz_buffer_init(&c->buf, cfg->slots,
                    (uint32_t)(cfg->m->n_commands + ROZ_DDS_CMD_META + cfg->n_extra));
    atomic_init(&c->shutdown, 0);
    atomic_init(&c->held_back, 0);
    roz_cmd_watchdog_init(&c->watchdog, cfg->timeout_us);
    for (size_t k = 0; k < ROZ_DDS_CMD_COUNTERS; k++)
        atomic_init(&c->count[k], 0u);
}

int roz_dds_cmd_attach(roz_dds_cmd_t *c, uint32_t spin_us)
{
    return roz_dds_writer_spin(c->writer, spin_us);
}

int roz_dds_cmd_start(roz_dds_cmd_t *c, uint32_t period_us, roz_monitor_t *monitor)
{
    uint32_t rate = c->m->control_rate_hz;
    /* event-driven: the safe command at the tick's rate, due by the path's clock */
    int rc = roz_dds_writer_watch(c->writer, &c->watchdog, rate < 1000000u ? 1000000u / rate : 1u,
                                  c->clock, c->clock_ctx);
    if (rc != ROZ_OK)
        return rc;
    atomic_store(&c->shutdown, 0);
    return roz_dds_writer_start(c->writer, period_us, pass, c, monitor);
}

int roz_dds_cmd_write(roz_dds_cmd_t *c, const double *cmd, size_t n, const roz_dds_cmd_tick_t *t)
{
    const roz_manifest_t *m = c->m;

    if (n != m->n_commands)
        return ROZ_EINVAL;
    bump(c, ROZ_DDS_CMD_WRITES);
    if (!t->has_state) {
        bump(c, ROZ_DDS_CMD_WITHHELD); /* nothing before the first state frame */
        return ROZ_OK;
    }
    uint64_t now = clock_now(c);
    uint32_t epoch;
    double *f = roz_buffer_write_begin(&c->buf);
    /* the first write for this robot, or since the watchdog tripped */
    int tripped = roz_cmd_watchdog_write(&c->watchdog, now, &epoch);
    int fresh = t->robot != c->write_robot; /* a robot new or restarted */
    int hold = tripped | fresh;
    if (hold) /* test_x2_watchdog_every_group, test_g1_watchdog_on_the_wire */
        c->hold_after_trip = tripped && !fresh;
    /* The hold is one frame of a latest-value hand-off: a write before the
     * writer sent it would overwrite it, and the robot's first command would
     * be the controller's. Until a pass sent it, every write is the hold
     * again (test_g1_hold_reaches_the_wire_first, test_x2_hold_reaches_the_
     * wire_first, test_pm01_hold_reaches_the_wire_first). */
    int again = !hold && c->hold_seq >
                             atomic_load_explicit(&c->count[ROZ_DDS_CMD_HOLD_SENT_SEQ],
                                                  memory_order_acquire);
    if (hold || again) {
        /* the start-up hold instead, or after a trip the stop's hold from
         * the tick's last command before it */
        c->ops->hold(c->port, c->hold_after_trip && c->has_last ? c->last_cmd : NULL, f);
        c->write_robot = t->robot;
        c->hold_seq = c->write_seq + 1u;
        if (hold)
            bump(c, ROZ_DDS_CMD_HOLDS);
        hold = 1;
    } else {
        uint32_t changed = roz_commands_clamp(m, cmd, f);
        memcpy(c->last_cmd, f, m->n_commands * sizeof f[0]);
        c->has_last = 1;
        if (changed != 0)
            atomic_fetch_add_explicit(&c->count[ROZ_DDS_CMD_CLAMPED], changed,
                                      memory_order_relaxed);
    }
    double *meta = f + m->n_commands;
    meta[C_SESSION] = t->session;
    meta[C_HOLD] = hold;
    meta[C_SEQ] = (double)++c->write_seq;
    meta[C_EPOCH] = epoch;
    if (c->n_extra != 0)
        memcpy(meta + ROZ_DDS_CMD_META, t->extra, c->n_extra * sizeof meta[0]);
    roz_buffer_write_commit(&c->buf, now); /* the watchdog judges its age */
    atomic_store_explicit(&c->count[ROZ_DDS_CMD_WRITTEN_SEQ], c->write_seq, memory_order_release);
    roz_dds_writer_wake(c->writer);
    return ROZ_OK;
}

int roz_dds_cmd_report(roz_dds_cmd_t *c, int rc, roz_port_fault_t *fault)
{
    if ((rc == 0 || rc == 1) &&
        roz_cmd_watchdog_report(&c->watchdog, clock_now(c), &fault->code)) {
        fault->what = ROZ_CMD_WATCHDOG_KEY;
        fault->kind = "the tick wrote no command for (us)";
        fault->limit = c->timeout_us;
        return ROZ_EWATCHDOG;
    }
    return rc;
}

int roz_dds_cmd_stop(roz_dds_cmd_t *c)
{
    roz_dds_writer_stop(c->writer);
    /* the last command (the port's exit), published here now the thread is gone */
    atomic_store_explicit(&c->shutdown, 1, memory_order_release);
    return roz_dds_writer_publish_final(c->writer, pass, c);
}

uint64_t roz_dds_cmd_count(const roz_dds_cmd_t *c, roz_dds_cmd_counter_t k)
{
    return atomic_load_explicit(&c->count[k], memory_order_acquire);
}

uint32_t roz_dds_cmd_timeouts(const roz_dds_cmd_t *c)
{
    return roz_cmd_watchdog_trips(&c->watchdog);
}
