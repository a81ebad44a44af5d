/* SPDX-License-Identifier: Apache-2.0 */
/* The port unitree/G1: parameters, the receive path (Cyclone's thread), the
 * tick's read, what LowCmd_ brings to roz/port/dds.h's command path (the hold,
 * the fill, the damping, mode_machine's lock), start-up and shutdown.
 * roz/port/unitree_g1.h says what it does; here is how. */
#include "roz/port/unitree_g1.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "g1_map.h"
#include "g1_rules.h"
#include "roz/filter.h"
#include "roz/hal/params.h"

/* ---- frame layouts ----------------------------------------------------------
 * State frame (receive thread -> tick): n_states values, then: */
enum { M_SESSION = 0, M_FAULT_SLOT, M_FAULT_CODE, M_MODE_MACHINE, M_TICK, M_Q };
/* Command frame (tick -> writer thread): roz/port/dds.h's command path, n_commands
 * values and its meta words, then the port's own: each slot's last finite
 * measured position (a joint without a position command is sent it). */

_Static_assert(M_Q + ROZ_UNITREE_G1_SLOTS == ROZ_UNITREE_G1_STATE_META, "state frame meta");
_Static_assert(ROZ_DDS_CMD_META + ROZ_UNITREE_G1_SLOTS == ROZ_UNITREE_G1_CMD_META,
               "command frame meta");
_Static_assert(sizeof(g1_cmd_t) == 4u * ROZ_UNITREE_G1_CMD_WORDS, "LowCmd_ storage");
_Static_assert(sizeof(g1_state_t) == 4u * ROZ_UNITREE_G1_STATE_WORDS, "LowState_ storage");

#define LOCKED 0x100u /* locked_mode_machine: a command went out */


/* ---- private ----------------------------------------------------------------- */

static void log_stderr(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    fprintf(stderr, "unitree/G1: %s: %s\n",
            level == ROZ_LOG_ERROR ? "error" : level == ROZ_LOG_WARN ? "warning" : "info", msg);
}

static uint64_t load(const ROZ_ATOMIC(uint64_t) *a)
{
    return atomic_load_explicit(a, memory_order_acquire);
}

static void bump(ROZ_ATOMIC(uint64_t) *a)
{
    atomic_fetch_add_explicit(a, 1u, memory_order_relaxed);
}


/* The rows the port's info shows (g1_rules.h). */
static const roz_port_param_info_t g1_params[] = { ROZ__G1_PARAM_ROWS };

static int parse_params(roz_unitree_g1_t *g1, const roz_params_t *p, char *err, size_t errlen)
{
    int rc = roz__g1_parse_params(g1, p, err, errlen, NULL, NULL);
    if (rc == ROZ_OK && g1->peer == ROZ_UNITREE_G1_PEER_UNITREE_MUJOCO &&
        getenv("CYCLONEDDS_URI") != NULL) {
        snprintf(err, errlen,
                 "parameter peer = \"unitree_mujoco\": CYCLONEDDS_URI is set, so roz cannot "
                 "keep the participant on lo; unset it to run the simulator");
        rc = ROZ_EINVAL;
    }
    return rc;
}

/* ---- the receive path (Cyclone's thread) ------------------------------------- */

static void on_lowstate(void *ctx, void *sample, uint64_t now_ns)
{
    roz_unitree_g1_t *g1 = ctx;
    const g1_state_t *s = sample;
    const roz_manifest_t *m = g1->m;
    uint32_t code;

    roz_dds_writer_expect(&g1->writer); /* the tick's command follows */
    bump(&g1->c_frames);
    roz_link_verdict_t v;
    if (g1->peer == ROZ_UNITREE_G1_PEER_UNITREE_MUJOCO) {
        /* no CRC, no tick: each arrival is the next frame, so what remains
         * of the link checks is the silence (peer_timeout_ms) and the
         * return after it; read_frame() stops a peer that sends a tick or
         * a mode_machine, as only a robot does */
        v = roz_link_check(&g1->link, 1, ++g1->arrivals, now_ns);
    } else {
        int crc_ok = roz__g1_state_crc_ok(s);
        if (!crc_ok && s->crc == 0u && s->tick == 0u && s->mode_machine == 0u)
            bump(&g1->c_sim_like); /* reported after the run (g1_report) */
        v = roz_link_check(&g1->link, crc_ok, s->tick, now_ns);
    }
    if (v == ROZ_LINK_BAD_CRC || v == ROZ_LINK_REPLAY) {
        roz_link_shared_publish(&g1->link_shared, &g1->link);
        return;
    }
    if (v == ROZ_LINK_FIRST || v == ROZ_LINK_RESTART) {
        /* a robot, new or restarted: its own session, converted whole */
        g1->session++;
        g1->since_full = 0;
        bump(&g1->c_sessions);
        atomic_store_explicit(&g1->rx_session, g1->session, memory_order_release);
    }
    int full = g1->since_full == 0;
    roz__g1_convert(g1, s, g1->rx_values, full);
    if (full)
        bump(&g1->c_full);
    g1->since_full = g1->since_full + 1u >= g1->dds.state_decimation ? 0u : g1->since_full + 1u;
    int slot = roz__g1_motor_fault(g1, s, &code);
    if (slot >= 0)
        bump(&g1->c_motor_fault);
    atomic_store_explicit(&g1->rx_mode_machine, s->mode_machine, memory_order_release);
    if (g1->operator_sink.remote != NULL) {
        /* the operator's remote, from an accepted frame only: wait-free
         * into the runtime's inputs */
        roz_operator_remote_t r;
        if (roz__g1_remote(s->wireless_remote, &r) > 0)
            bump(&g1->c_remote_nonfinite);
        (void)g1->operator_sink.remote(g1->operator_sink.ctx, &r);
        bump(&g1->c_remote);
    }

    double *f = roz_buffer_write_begin(&g1->state_buf);
    memcpy(f, g1->rx_values, (size_t)m->n_states * sizeof f[0]);
    double *meta = f + m->n_states;
    meta[M_SESSION] = g1->session;
    meta[M_FAULT_SLOT] = slot;
    meta[M_FAULT_CODE] = code;
    meta[M_MODE_MACHINE] = s->mode_machine;
    meta[M_TICK] = s->tick;
    for (int k = 0; k < ROZ_UNITREE_G1_SLOTS; k++)
        meta[M_Q + k] = s->motor_state[k].q;
    roz_buffer_write_commit(&g1->state_buf, now_ns);
    /* last: whoever waits on the counters finds the frame in the buffer */
    roz_link_shared_publish(&g1->link_shared, &g1->link);
}

/* Whether mode_machine @p mm is a variant without a motor for one of the
 * manifest's joints (any thread: reads what open set). */
static int g1_variant_refuses(const roz_unitree_g1_t *g1, uint32_t mm)
{
    const char *why;
    return roz__g1_variant_refuses(g1, mm, &why) >= 0;
}

/* ---- the command path's hooks (roz/port/dds.h says which thread runs each) -------- */

static void g1_hold(void *port, const double *last, double *cmd)
{
    roz_unitree_g1_t *g1 = port;
    roz__g1_hold(g1, g1->tick_q, last, last != NULL ? g1->shutdown_kd : g1->startup_kd, cmd);
}

static uint32_t g1_rx_session(void *port)
{
    roz_unitree_g1_t *g1 = port;
    return atomic_load_explicit(&g1->rx_session, memory_order_acquire);
}

/* mode_machine changed under the controller, or the robot is a variant
 * without a motor the manifest drives; mode_machine is loaded before the
 * session (the receive path stores it after), and kept for g1_send() */
static int g1_refuse(void *port)
{
    roz_unitree_g1_t *g1 = port;
    uint32_t locked = atomic_load_explicit(&g1->locked_mode_machine, memory_order_relaxed);
    uint32_t mm = atomic_load_explicit(&g1->rx_mode_machine, memory_order_acquire);

    g1->tx_mode_machine = mm;
    /* peer = unitree_mujoco, and a robot answers: nothing at all for it */
    if (g1->peer == ROZ_UNITREE_G1_PEER_UNITREE_MUJOCO && mm != 0u)
        return 1;
    return (locked && (locked & 0xffu) != mm) || g1_variant_refuses(g1, mm);
}

static int g1_send(void *port, void *sample, const double *cmd, const double *extra, int hold)
{
    roz_unitree_g1_t *g1 = port;
    g1_cmd_t *out = sample;
    uint32_t mm = g1->tx_mode_machine;

    if (!atomic_load_explicit(&g1->locked_mode_machine, memory_order_relaxed))
        atomic_store_explicit(&g1->locked_mode_machine, LOCKED | mm, memory_order_release);
    roz__g1_fill(g1, cmd, extra, (uint8_t)mm, out);
    /* the watchdog's hold is the controller's last command's, never that
     * of a hold the port made up (test_g1_trip_write_trip_keeps_the_torque) */
    for (uint16_t k = 0; k < g1->n_joints; k++) {
        g1->tx_meas_q[k] = extra[g1->slot[k]];
        if (hold && g1->tx_ctrl)
            continue;
        g1->tx_last_q[k] = out->motor_cmd[g1->slot[k]].q;
        g1->tx_last_kp[k] = out->motor_cmd[g1->slot[k]].kp;
    }
    g1->tx_ctrl |= !hold; /* until then the start-up hold's: the measured positions */
    return 1;
}

static int g1_watchdog(void *port, void *sample);

/* The last command on the way out: the stop's hold (the humanoid's stop,
 * test_g1_exit_is_the_hold), or damping where exit_stop chose it */
static int g1_safe(void *port, void *sample)
{
    roz_unitree_g1_t *g1 = port;
    if (!g1->dds.exit_damping)
        return g1_watchdog(port, sample);
    uint32_t locked = atomic_load_explicit(&g1->locked_mode_machine, memory_order_relaxed);
    roz__g1_fill_damping(g1, g1->tx_last_q, g1->shutdown_kd, 0, (uint8_t)(locked & 0xffu),
                         sample);
    return 1;
}

/* The tick is silent: the stop's hold from the controller's last command
 * (roz_joints_hold_setpoint(): the hold gain, the torque kept within the
 * band of the measured position, a joint without a position command at its
 * measured position; test_mujoco_stops_g1, the balancing stand's watchdog
 * row; test_g1_watchdog_hold_rules) */
static int g1_watchdog(void *port, void *sample)
{
    roz_unitree_g1_t *g1 = port;
    double q[ROZ_UNITREE_G1_SLOTS];
    uint32_t locked = atomic_load_explicit(&g1->locked_mode_machine, memory_order_relaxed);
    for (uint16_t k = 0; k < g1->n_joints; k++)
        q[k] = roz_joints_hold_setpoint(g1->m, &g1->joint[k], g1->tx_last_q[k],
                                        g1->tx_last_kp[k], g1->tx_meas_q[k]);
    roz__g1_fill_damping(g1, q, g1->shutdown_kd, 1, (uint8_t)(locked & 0xffu), sample);
    return 1;
}

static const roz_dds_cmd_ops_t g1_cmd_ops = {
    .hold = g1_hold,
    .rx_session = g1_rx_session,
    .refuse = g1_refuse,
    .send = g1_send,
    .safe = g1_safe,
    .watchdog = g1_watchdog,
};

/* ---- ops ------------------------------------------------------------------------ */

static void g1_close(void *self);

static int g1_open(void *self, const roz_manifest_t *m, const roz_params_t *p, char *err,
                   size_t errlen)
{
    roz_unitree_g1_t *g1 = self;
    roz_log_fn log = g1->log != NULL ? g1->log : log_stderr;
    void *log_ctx = g1->log_ctx;
    roz_params_t params;
    int rc;

    if (g1->open)
        g1_close(g1);
    memset(g1, 0, sizeof *g1);
    g1->log = log;
    g1->log_ctx = log_ctx;
    for (uint16_t k = 0; k < ROZ_UNITREE_G1_SLOTS; k++)
        g1->tick_q[k] = NAN; /* no position measured yet */
    if (m == NULL || roz_manifest_validate(m, NULL) != ROZ_OK) {
        snprintf(err, errlen, "unitree/G1: invalid manifest");
        return ROZ_EINVAL;
    }
    g1->m = m;
    rc = roz__g1_bind(g1, m, err, errlen) == ROZ_OK ? ROZ_OK : ROZ_EINVAL;
    if (rc == ROZ_OK) /* robot.toml's [hardware.params] first, then the caller's */
        rc = roz_params_merge(m, p, g1->params, ROZ_UNITREE_G1_MAX_PARAMS, "unitree/G1", &params,
                              err, errlen);
    if (rc == ROZ_OK)
        rc = parse_params(g1, &params, err, errlen);
    if (rc != ROZ_OK)
        return rc;

    roz_link_init(&g1->link, (uint64_t)g1->peer_timeout_ms * 1000000u, 0);
    roz_link_shared_init(&g1->link_shared);
    roz_link_shared_publish(&g1->link_shared, &g1->link);
    roz_buffer_init(&g1->state_buf, g1->state_slots,
                    (uint32_t)(m->n_states + ROZ_UNITREE_G1_STATE_META));
    uint64_t period_ns = g1->dds.command_writer_period_us != 0
                             ? (uint64_t)g1->dds.command_writer_period_us * 1000u
                             : 1000000000u / m->control_rate_hz;
    roz_monitor_init(&g1->mon_rx, "unitree/G1 state", period_ns, log, log_ctx);
    roz_monitor_init(&g1->mon_tx, "unitree/G1 command writer", period_ns, log, log_ctx);
    atomic_init(&g1->rx_session, 0u);
    atomic_init(&g1->rx_mode_machine, 0u);
    atomic_init(&g1->locked_mode_machine, 0u);
    roz_dds_cmd_config_t cmd = { .m = m, .ops = &g1_cmd_ops, .port = g1, .writer = &g1->writer,
                                 .slots = g1->cmd_slots, .n_extra = ROZ_UNITREE_G1_SLOTS,
                                 .timeout_us = g1->dds.command_timeout_us };
    roz_dds_cmd_init(&g1->cmd, &cmd);
    ROZ_ATOMIC(uint64_t) *counters[] = { &g1->c_frames,   &g1->c_full,     &g1->c_motor_fault,
                                         &g1->c_sessions, &g1->c_sim_like, &g1->c_remote,
                                         &g1->c_remote_nonfinite };
    for (size_t i = 0; i < sizeof counters / sizeof counters[0]; i++)
        atomic_init(counters[i], 0u);

    if (g1->peer == ROZ_UNITREE_G1_PEER_UNITREE_MUJOCO)
        log(log_ctx, ROZ_LOG_WARN,
            "peer = unitree_mujoco: no state CRC and no tick checks (the link is judged by "
            "arrival alone), for Unitree's simulator on lo; never use it with a robot");
    rc = roz_dds_participant_open(&g1->part, g1->dds.network_interface, g1->dds.domain,
                                  &g1->dds.cyclone_threads, log,
                                  log_ctx, err, errlen);
    if (rc == ROZ_OK)
        rc = roz_dds_writer_open(&g1->writer, &g1->part, "rt/lowcmd",
                                 &unitree_hg_msg_dds__LowCmd__desc, &roz_dds_qos_robot_command,
                                 g1->tx_sample, sizeof g1->tx_sample, err, errlen);
    if (rc == ROZ_OK)
        rc = roz_dds_cmd_attach(&g1->cmd, g1->dds.command_writer_spin_us);
    g1->open = 1;
    if (rc != ROZ_OK)
        g1_close(g1);
    return rc;
}

static int g1_activate(void *self)
{
    roz_unitree_g1_t *g1 = self;
    char err[200];

    if (!g1->open)
        return ROZ_ESTATE;
    if (g1->active)
        return ROZ_OK;
    int rc = roz_dds_reader_open(&g1->reader, &g1->part, "rt/lowstate",
                                 &unitree_hg_msg_dds__LowState__desc, &roz_dds_qos_robot_state,
                                 g1->rx_sample, sizeof g1->rx_sample, on_lowstate, g1,
                                 g1->dds.enable_monitor ? &g1->mon_rx : NULL, err, sizeof err);
    if (rc != ROZ_OK) {
        g1->log(g1->log_ctx, ROZ_LOG_ERROR, err);
        return rc;
    }
    roz_dds_writer_set_thread(&g1->writer, &g1->dds.writer_thread);
    rc = roz_dds_cmd_start(&g1->cmd, g1->dds.command_writer_period_us,
                           g1->dds.enable_monitor ? &g1->mon_tx : NULL);
    if (rc != ROZ_OK) {
        if (roz_dds_writer_thread_error(&g1->writer)[0] != '\0') {
            snprintf(err, sizeof err, "unitree/G1: %s", roz_dds_writer_thread_error(&g1->writer));
            g1->log(g1->log_ctx, ROZ_LOG_ERROR, err);
        }
        roz_dds_reader_close(&g1->reader);
        return rc;
    }
    g1->active = 1;
    return ROZ_OK;
}

static int read_frame(roz_unitree_g1_t *g1, double *state, size_t n)
{
    roz_buffer_frame_t f;

    g1->tick_fault.what = NULL; /* fault() speaks of this read only (roz/port.h) */
    if (roz_buffer_read(&g1->state_buf, &f) == ROZ_ENOENT)
        return ROZ_ENOENT;
    memcpy(state, f.values, n * sizeof state[0]);
    if (!f.fresh)
        return 0;
    const double *meta = f.values + n;
    g1->tick_has_state = 1;
    /* the positions a joint without a position command is sent: the last
     * finite one of each slot (test_g1_wire_inside_the_manifest) */
    for (uint16_t k = 0; k < ROZ_UNITREE_G1_SLOTS; k++) {
        if (isfinite(meta[M_Q + k]))
            g1->tick_q[k] = meta[M_Q + k];
    }

    uint32_t session = (uint32_t)meta[M_SESSION];
    if (session != g1->tick_session) {
        int first = g1->tick_session == 0;
        g1->tick_session = session;
        if (!first)
            return ROZ_ELINK; /* a restarted robot: its start-up layers begin again */
    }
    int slot = (int)meta[M_FAULT_SLOT];
    if (slot >= 0) {
        g1->tick_fault.what = g1->m->hardware->joints[slot];
        g1->tick_fault.kind = "motor fault code";
        g1->tick_fault.code = (uint32_t)meta[M_FAULT_CODE];
        g1->tick_fault.limit = 0;
        return ROZ_EROBOT;
    }
    uint32_t locked = atomic_load_explicit(&g1->locked_mode_machine, memory_order_acquire);
    uint32_t mm = (uint32_t)meta[M_MODE_MACHINE];
    if (g1->peer == ROZ_UNITREE_G1_PEER_UNITREE_MUJOCO && (mm != 0u || meta[M_TICK] != 0.0)) {
        /* a peer that counts ticks or names its variant is a robot: the
         * checks it would need are off (test_g1_sim) */
        g1->tick_fault.what = "peer = unitree_mujoco";
        g1->tick_fault.kind = mm != 0u ? "but the peer reports a robot's mode_machine"
                                       : "but the peer counts ticks as a robot does; tick";
        g1->tick_fault.code = mm != 0u ? mm : (uint32_t)meta[M_TICK];
        g1->tick_fault.limit = 0;
        return ROZ_EROBOT;
    }
    const char *why;
    int absent = roz__g1_variant_refuses(g1, mm, &why);
    if (absent >= 0) {
        g1->tick_fault.what = g1->m->hardware->joints[absent];
        g1->tick_fault.kind = why;
        g1->tick_fault.code = mm;
        g1->tick_fault.limit = 0;
        return ROZ_EROBOT;
    }
    if (locked && (locked & 0xffu) != mm) {
        g1->tick_fault.what = "mode_machine";
        g1->tick_fault.kind = "changed under a running controller (nothing is sent), now";
        g1->tick_fault.code = mm;
        g1->tick_fault.limit = 0;
        return ROZ_EROBOT;
    }
    return 1;
}

static int g1_read(void *self, double *state, size_t n)
{
    roz_unitree_g1_t *g1 = self;

    if (!g1->open || n != g1->m->n_states)
        return ROZ_EINVAL;
    return roz_dds_cmd_report(&g1->cmd, read_frame(g1, state, n), &g1->tick_fault);
}

static int g1_write(void *self, const double *cmd, size_t n)
{
    roz_unitree_g1_t *g1 = self;

    if (!g1->open)
        return ROZ_EINVAL;
    /* a robot is a session of LowState_: a restart, or a return after
     * peer_timeout_ms, is a new one */
    roz_dds_cmd_tick_t t = { .has_state = g1->tick_has_state, .robot = g1->tick_session,
                             .session = g1->tick_session, .extra = g1->tick_q };
    return roz_dds_cmd_write(&g1->cmd, cmd, n, &t);
}

static int g1_deactivate(void *self)
{
    roz_unitree_g1_t *g1 = self;

    if (!g1->active)
        return ROZ_OK;
    (void)roz_dds_cmd_stop(&g1->cmd); /* the last command: the exit stop */
    roz_dds_reader_close(&g1->reader);
    g1->active = 0;
    return ROZ_OK;
}

static void g1_close(void *self)
{
    roz_unitree_g1_t *g1 = self;

    if (!g1->open)
        return;
    (void)g1_deactivate(g1);
    roz_dds_writer_close(&g1->writer);
    roz_dds_participant_close(&g1->part);
    g1->open = 0;
}

/* Read by the receive thread, which activate starts: set before it. */
static int g1_set_operator(void *self, const roz_operator_sink_t *sink)
{
    roz_unitree_g1_t *g1 = self;

    if (sink == NULL)
        return ROZ_EINVAL;
    if (!g1->open || g1->active)
        return ROZ_ESTATE;
    g1->operator_sink = *sink;
    return ROZ_OK;
}

static int g1_fault(void *self, roz_port_fault_t *out)
{
    roz_unitree_g1_t *g1 = self;
    *out = g1->tick_fault;
    return ROZ_OK;
}

static int g1_link_counters(const void *self, roz_port_link_counters_t *out)
{
    roz_link_t l;
    roz_unitree_g1_link(self, &l);
    roz_link_port_counters(&l, 0, out);
    return ROZ_OK;
}

/* peer = unitree_mujoco at open and after the run; a run that dropped the
 * simulator's frames names the setting (test_g1_sim) */
static int g1_report(const void *self, roz_port_report_when_t when, char *buf, size_t len)
{
    const roz_unitree_g1_t *g1 = self;
    int sim = g1->peer == ROZ_UNITREE_G1_PEER_UNITREE_MUJOCO;
    uint64_t like = load(&g1->c_sim_like);
    int n = 0;

    if (when == ROZ_PORT_REPORT_OPENED && sim)
        n = snprintf(buf, len, "unitree/G1: peer = unitree_mujoco (Unitree's simulator, "
                               "domain %u on lo): no state CRC, no tick checks; never a robot",
                     (unsigned)g1->dds.domain);
    else if (when == ROZ_PORT_REPORT_SUMMARY && sim)
        n = snprintf(buf, len,
                     "peer                   unitree_mujoco (simulator): frames taken without "
                     "a CRC or tick check, the link judged by arrival alone");
    else if (when == ROZ_PORT_REPORT_SUMMARY && like > 0u)
        n = snprintf(buf, len,
                     "warning                %llu state frames dropped for their CRC had crc, "
                     "tick and mode_machine all 0, as unitree_mujoco sends them: for that "
                     "simulator, --param peer=unitree_mujoco",
                     (unsigned long long)like);
    else if (len > 0)
        buf[0] = '\0';
    return n;
}


static const roz_port_info_t g1_info = {
    .summary = "the Unitree G1 over Cyclone DDS (unitree_hg LowCmd_/LowState_, CRC32)",
    .header = "roz/port/unitree_g1.h",
    ROZ_PORT_INFO_PARAMS(g1_params),
};

/* The receive and writer threads' warnings, said here (roz/port.h drain). */
static size_t g1_drain(void *self)
{
    roz_unitree_g1_t *g1 = self;
    return roz_monitor_drain(&g1->mon_rx) + roz_monitor_drain(&g1->mon_tx);
}

const roz_port_ops_t roz_unitree_g1_ops = {
    .name = "unitree/G1",
    .open = g1_open,
    .activate = g1_activate,
    .read = g1_read,
    .write = g1_write,
    .deactivate = g1_deactivate,
    .close = g1_close,
    .fault = g1_fault,
    .caps = ROZ_PORT_CAP_CRC | ROZ_PORT_CAP_SEQUENCE | ROZ_PORT_CAP_WATCHDOG |
            ROZ_PORT_CAP_START_HOLD | ROZ_PORT_CAP_ROBOT | ROZ_PORT_CAP_NEEDS_NETNS,
    .info = &g1_info,
    .link_counters = g1_link_counters,
    .drain = g1_drain,
    .report = g1_report,
    .set_operator = g1_set_operator,
};

/* ---- public ------------------------------------------------------------------------ */

roz_port_t roz__unitree_g1_port(roz_unitree_g1_t *g1, const roz_port_layout_t *caller,
                                size_t bytes, roz_log_fn log, void *log_ctx)
{
    roz_port_t p = roz_port_make(&roz_unitree_g1_ops, g1, caller, bytes, sizeof *g1);
    if (p.self == NULL)
        return p; /* misbuilt: nothing written to *g1 */
    g1->open = 0;
    g1->log = log;
    g1->log_ctx = log_ctx;
    return p;
}

void roz_unitree_g1_link(const roz_unitree_g1_t *g1, roz_link_t *out)
{
    (void)roz_link_shared_read(&g1->link_shared, out);
}

void roz_unitree_g1_counters(const roz_unitree_g1_t *g1, roz_unitree_g1_counters_t *out)
{
    memset(out, 0, sizeof *out);
    out->frames = load(&g1->c_frames);
    out->full_conversions = load(&g1->c_full);
    out->motor_fault_frames = load(&g1->c_motor_fault);
    out->sessions = load(&g1->c_sessions);
    out->writes = roz_dds_cmd_count(&g1->cmd, ROZ_DDS_CMD_WRITES);
    out->writes_withheld = roz_dds_cmd_count(&g1->cmd, ROZ_DDS_CMD_WITHHELD);
    out->holds = roz_dds_cmd_count(&g1->cmd, ROZ_DDS_CMD_HOLDS);
    out->clamped = roz_dds_cmd_count(&g1->cmd, ROZ_DDS_CMD_CLAMPED);
    /* done before passes: a pass that ends between the two loads shows as
     * open, never the other way round */
    out->writer_done = load(&g1->writer.done);
    out->writer_passes = load(&g1->writer.passes);
    out->published = load(&g1->writer.published);
    out->publish_errors = load(&g1->writer.errors);
    out->stale_session = roz_dds_cmd_count(&g1->cmd, ROZ_DDS_CMD_STALE);
    out->refused_mode_machine = roz_dds_cmd_count(&g1->cmd, ROZ_DDS_CMD_REFUSED);
    out->handled_seq = roz_dds_cmd_count(&g1->cmd, ROZ_DDS_CMD_HANDLED_SEQ);
    out->written_seq = roz_dds_cmd_count(&g1->cmd, ROZ_DDS_CMD_WRITTEN_SEQ);
    out->command_timeouts = roz_dds_cmd_timeouts(&g1->cmd);
    out->safe_published = roz_dds_cmd_count(&g1->cmd, ROZ_DDS_CMD_SAFE);
    out->sim_like_frames = load(&g1->c_sim_like);
    out->remote_frames = load(&g1->c_remote);
    out->remote_nonfinite = load(&g1->c_remote_nonfinite);
}

void roz_unitree_g1_matched(const roz_unitree_g1_t *g1, uint32_t *cmd_readers,
                            uint32_t *state_writers)
{
    *cmd_readers = roz_dds_writer_matched(&g1->writer);
    *state_writers = roz_dds_reader_matched(&g1->reader);
}

const roz_dds_participant_t *roz_unitree_g1_participant(const roz_unitree_g1_t *g1)
{
    return &g1->part;
}

const roz_monitor_t *roz_unitree_g1_writer_monitor(const roz_unitree_g1_t *g1)
{
    return &g1->mon_tx;
}

const roz_monitor_t *roz_unitree_g1_state_monitor(const roz_unitree_g1_t *g1)
{
    return &g1->mon_rx;
}
