/* SPDX-License-Identifier: Apache-2.0 */
/* The bridge between a robot's ROS 2 joint-group topics and roz's port
 * contract: parameters, the receive path of each state topic (a Cyclone
 * thread), the tick's read (gathering the topics into one frame), what the
 * joint-group topics bring to roz/port/dds.h's command path (one pass publishes
 * every group's), start-up and shutdown. roz/port/ros2.h says what it does; here
 * is how. */
#include "roz/port/ros2.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "ros2_map.h"
#include "ros2_msgs.h"
#include "roz/filter.h"
#include "roz/hal/params.h"
#include "roz/runtime.h"

/* ---- frame layouts -------------------------------------------------------------
 * A state topic's frame (receive thread -> tick): its values, then: */
enum { M_SESSION = 0, M_FAULT_KIND, M_FAULT_SLOT, M_FAULT_CODE, M_FAULT_SERIAL };
/* Command frame (tick -> writer thread): roz/port/dds.h's command path, n_commands
 * values and its meta words, then the bridge's own: each robot slot's
 * measured position (a slot the frame does not command holds it). */

_Static_assert(M_FAULT_SERIAL + 1 == ROZ_ROS2_STATE_META, "state frame meta");
_Static_assert(ROZ_DDS_CMD_META + ROZ_ROS2_MAX_ROBOT_SLOTS == ROZ_ROS2_CMD_META,
               "command frame meta");
_Static_assert(ROZ_ROS2_MAX_TOPICS <= 32, "a bit per topic");

#define FRAME_ID_ROOM 63 /* characters a received frame_id gets without Cyclone reallocating */

enum { OP_TWIST = 0, OP_JOY = 1 }; /* b->op[] */
typedef geometry_msgs_msg_dds__Twist_ twist_t;
typedef sensor_msgs_msg_dds__Joy_ joy_t;
_Static_assert(sizeof(twist_t) <= sizeof(((roz_ros2_op_topic_t *)0)->sample), "Twist_ storage");
_Static_assert(sizeof(joy_t) <= sizeof(((roz_ros2_op_topic_t *)0)->sample), "Joy_ storage");

/* ---- private ---------------------------------------------------------------------- */

static void log_stderr(void *ctx, roz_log_level_t level, const char *msg)
{
    (void)ctx;
    fprintf(stderr, "%s: %s\n",
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

/* An operator sample counted after its outcome (handed or refused), with
 * release order: a reader whose acquire load (roz_ros2_counters) sees the
 * sample sees its outcome too, so the counters never show a sample that was
 * neither handed nor refused while it is being handled. */
static void counted(ROZ_ATOMIC(uint64_t) *a)
{
    atomic_fetch_add_explicit(a, 1u, memory_order_release);
}

static int reads(const roz_ros2_bridge_t *b, uint16_t t)
{
    return (b->required >> t) & 1u;
}

static int is_imu(const roz_ros2_bridge_t *b, uint16_t t)
{
    return t == b->robot->n_groups;
}

/* The group of the first command writer (the one with the thread). */
static uint16_t primary(const roz_ros2_bridge_t *b)
{
    for (uint16_t g = 0; g < b->robot->n_groups; g++) {
        if (reads(b, g))
            return g;
    }
    return 0;
}


/* ---- the receive path (a Cyclone thread per topic, one call at a time) --------- */

/* A malformed sample: kept once per topic and kind as numbers, for
 * roz_ros2_drain() to say on the application's thread (this thread never
 * formats text nor calls the log: test_port_conformance blocking_log). The
 * numbers are published before the bit that announces them. */
static void say_once(roz_ros2_topic_t *t, roz_ros2_bad_t why, const roz_ros2_rx_t *rx)
{
    uint32_t bit = 1u << (unsigned)why;

    if (atomic_load_explicit(&t->said, memory_order_relaxed) & bit)
        return;
    atomic_store_explicit(&t->said_a[why], rx->bad_a, memory_order_relaxed);
    atomic_store_explicit(&t->said_b[why], rx->bad_b, memory_order_relaxed);
    atomic_fetch_or_explicit(&t->said, bit, memory_order_release);
}

static void format_bad(const roz_ros2_bridge_t *b, const roz_ros2_topic_t *t, roz_ros2_bad_t why,
                       int32_t bad_a, int32_t bad_b, char *msg, size_t len)
{
    switch (why) {
    case ROZ_ROS2_BAD_LENGTH:
        snprintf(msg, len,
                 "%s: %s: a sample with %d joint values, expected %d: dropped (counted; said "
                 "once)",
                 b->robot->port, t->name, (int)bad_a, (int)bad_b);
        break;
    case ROZ_ROS2_BAD_NAME:
        snprintf(msg, len,
                 "%s: %s: the joint in slot %d is not named \"%s\": the robot's joint order is "
                 "not the port's; dropped (counted; said once)",
                 b->robot->port, t->name, (int)bad_a,
                 bad_a >= 0 && bad_a < (int32_t)b->robot->groups[t->index].n_slots
                     ? b->robot->groups[t->index].slots[bad_a]
                     : "?");
        break;
    default:
        snprintf(msg, len,
                 "%s: %s: a header stamp that is not a time (sec < 0 or nanosec > 999999999): "
                 "dropped (counted; said once)",
                 b->robot->port, t->name);
        break;
    }
}

size_t roz_ros2_drain(void *self)
{
    roz_ros2_bridge_t *b = self;
    size_t n = 0;
    char msg[320];

    if (!b->open)
        return 0;
    for (uint16_t i = 0; i < b->n_topics; i++) {
        roz_ros2_topic_t *t = &b->topic[i];
        uint32_t said = atomic_load_explicit(&t->said, memory_order_acquire) & ~t->told;
        for (unsigned why = ROZ_ROS2_BAD_LENGTH; why <= ROZ_ROS2_BAD_STAMP; why++) {
            if (!(said & (1u << why)))
                continue;
            format_bad(b, t, (roz_ros2_bad_t)why,
                       atomic_load_explicit(&t->said_a[why], memory_order_relaxed),
                       atomic_load_explicit(&t->said_b[why], memory_order_relaxed), msg,
                       sizeof msg);
            b->log(b->log_ctx, ROZ_LOG_ERROR, msg);
            n++;
        }
        t->told |= said;
        n += roz_monitor_drain(&t->mon);
    }
    return n + roz_monitor_drain(&b->mon_tx);
}

/* Checks and converts the sample into t->scratch (rx): the port's decode for
 * a group, the IMU's values (when full) for the IMU. */
static roz_ros2_bad_t convert(roz_ros2_topic_t *t, const void *sample, int full,
                              roz_ros2_rx_t *rx)
{
    roz_ros2_bridge_t *b = t->bridge;
    const roz_ros2_robot_t *r = b->robot;

    memset(rx, 0, sizeof *rx);
    rx->fault_slot = -1;
    if (is_imu(b, t->index)) {
        if (full)
            r->decode_imu(sample, t->scratch);
        return ROZ_ROS2_GOOD;
    }
    uint16_t n = r->groups[t->index].n_slots;
    rx->q = t->scratch;
    rx->dq = t->scratch + n;
    rx->tau = t->scratch + 2u * n;
    return r->decode(b->vendor, t->index, sample, full, rx);
}

static void on_sample(void *ctx, void *sample, uint64_t now_ns)
{
    roz_ros2_topic_t *t = ctx;
    roz_ros2_bridge_t *b = t->bridge;
    const roz_ros2_robot_t *r = b->robot;
    roz_ros2_header_t h = { 0, 0, 0 };
    roz_ros2_rx_t rx;
    uint32_t seq = 0;
    int imu = is_imu(b, t->index);

    /* a state sample: the tick's command follows (a spinning writer wakes) */
    roz_dds_writer_expect(&b->out[primary(b)].writer);
    bump(&t->c_samples);
    if (imu) {
        const std_msgs_msg_dds__Header_ *sh = sample; /* the IMU's struct starts with it */
        h.sec = sh->stamp.sec;
        h.nanosec = sh->stamp.nanosec;
    } else {
        r->state_header(b->vendor, sample, &h);
    }
    int full = t->since_full == 0 || !t->link.alive;
    roz_ros2_bad_t why = convert(t, sample, full, &rx);
    if (why == ROZ_ROS2_GOOD) {
        if (imu || b->link_by_stamp) {
            if (!roz_ros2_stamp_seq(h.sec, h.nanosec, &seq))
                why = ROZ_ROS2_BAD_STAMP;
        } else {
            seq = h.sequence;
        }
    }
    if (why != ROZ_ROS2_GOOD) {
        bump(&t->c_malformed);
        say_once(t, why, &rx);
        roz_link_shared_publish(&t->link_shared, &t->link);
        return;
    }
    roz_link_verdict_t v = roz_link_check(&t->link, 1, seq, now_ns);
    if (v == ROZ_LINK_REPLAY || v == ROZ_LINK_BAD_CRC) {
        roz_link_shared_publish(&t->link_shared, &t->link);
        return;
    }
    if (v == ROZ_LINK_FIRST || v == ROZ_LINK_RESTART) {
        /* a peer, new or restarted: its own session, converted whole */
        t->session++;
        t->since_full = 0;
        bump(&t->c_sessions);
        atomic_store_explicit(&t->rx_session, t->session, memory_order_release);
        if (!full) {
            full = 1;
            (void)convert(t, sample, 1, &rx);
        }
    }
    full = t->since_full == 0;
    if (imu) {
        if (full)
            memcpy(t->values, t->scratch, ROZ_IMU_VALUES * sizeof t->values[0]);
    } else {
        /* positions every sample; velocities and efforts when full */
        uint16_t n = r->groups[t->index].n_slots;
        memcpy(t->values, t->scratch, (full ? 3u : 1u) * n * sizeof t->values[0]);
    }
    if (full)
        bump(&t->c_full);
    t->since_full = t->since_full + 1u >= b->dds.state_decimation ? 0u : t->since_full + 1u;
    /* A fault is held until the tick took a frame that carries it: the
     * buffer keeps only the latest frame, and a clean sample may follow
     * before the tick reads. A new fault is held when none is. */
    uint32_t ack = atomic_load_explicit(&t->fault_ack, memory_order_acquire);
    if (rx.fault_kind != 0) {
        bump(&t->c_fault);
        if (t->held_serial == ack) {
            t->held_kind = rx.fault_kind;
            t->held_slot = rx.fault_slot;
            t->held_code = rx.fault_code;
            t->held_serial++;
        }
    } else if (t->held_serial != ack) {
        rx.fault_kind = t->held_kind;
        rx.fault_slot = t->held_slot;
        rx.fault_code = t->held_code;
    }

    double *f = roz_buffer_write_begin(&t->buf);
    memcpy(f, t->values, t->n_values * sizeof f[0]);
    double *meta = f + t->n_values;
    meta[M_SESSION] = t->session;
    meta[M_FAULT_KIND] = rx.fault_kind;
    meta[M_FAULT_SLOT] = rx.fault_slot;
    meta[M_FAULT_CODE] = rx.fault_code;
    meta[M_FAULT_SERIAL] = t->held_serial;
    roz_buffer_write_commit(&t->buf, now_ns);
    /* last: whoever waits on the counters finds the frame in the buffer */
    roz_link_shared_publish(&t->link_shared, &t->link);
}

/* ---- the operator topics' receive path (a Cyclone thread each) ------------------ */

/* The sink roz_ros2_set_operator() stored, once it is there (Cyclone's
 * threads run from open, the sink comes after it), else NULL. */
static const roz_operator_sink_t *op_sink(roz_ros2_bridge_t *b)
{
    return atomic_load_explicit(&b->op_set, memory_order_acquire) ? &b->op_sink : NULL;
}

/* A twist as sent; the runtime's inputs refuse what is not finite and
 * clamp the rest (roz/inputs.h). */
static void on_twist(void *ctx, void *sample, uint64_t now_ns)
{
    roz_ros2_op_topic_t *t = ctx;
    const twist_t *tw = sample;
    roz_operator_twist_t f = { { tw->linear.x, tw->linear.y, tw->linear.z },
                               { tw->angular.x, tw->angular.y, tw->angular.z } };
    const roz_operator_sink_t *sink = op_sink(t->bridge);
    (void)now_ns;
    if (sink != NULL && sink->twist != NULL && sink->twist(sink->ctx, &f) == ROZ_OK)
        bump(&t->c_handed);
    counted(&t->c_samples);
}

/* A Joy through joy_map; one that does not fit the map, has a mapped axis
 * that is not a number, or has more axes or buttons than ROZ_ROS2_JOY_MAX
 * (its sequences arrive ROZ_ROS2_JOY_MAX + 1 long: reserve_joy()), is
 * refused whole (no half of a pad's frame). */
static void on_joy(void *ctx, void *sample, uint64_t now_ns)
{
    roz_ros2_op_topic_t *t = ctx;
    const joy_t *j = sample;
    roz_operator_remote_t r;
    const roz_operator_sink_t *sink = op_sink(t->bridge);
    (void)now_ns;
    int rc = roz_joy_remote(&t->bridge->joy_map, j->axes._buffer, j->axes._length,
                            j->buttons._buffer, j->buttons._length, &r);
    if (rc == ROZ_ENOSPC)
        bump(&t->c_oversized);
    if (rc != ROZ_OK)
        bump(&t->c_refused);
    else if (sink != NULL && sink->remote != NULL && sink->remote(sink->ctx, &r) == ROZ_OK)
        bump(&t->c_handed);
    counted(&t->c_samples);
}

int roz_ros2_set_operator(void *self, const roz_operator_sink_t *sink)
{
    roz_ros2_bridge_t *b = self;

    if (sink == NULL)
        return ROZ_EINVAL;
    if (!b->open || atomic_load_explicit(&b->op_set, memory_order_relaxed))
        return ROZ_ESTATE; /* after open, once: Cyclone's threads may read it from now */
    b->op_sink = *sink;
    atomic_store_explicit(&b->op_set, 1, memory_order_release);
    return ROZ_OK;
}

static int open_operator(roz_ros2_bridge_t *b, char *err, size_t errlen)
{
    int rc = ROZ_OK;
    roz_ros2_op_topic_t *tw = &b->op[OP_TWIST], *jo = &b->op[OP_JOY];
    if (tw->name[0] != '\0')
        rc = roz_dds_reader_open(&tw->reader, &b->part, tw->name,
                                 &geometry_msgs_msg_dds__Twist__desc, &roz_dds_qos_robot_state,
                                 tw->sample, sizeof(twist_t), on_twist, tw, NULL, err, errlen);
    if (rc == ROZ_OK && jo->name[0] != '\0')
        rc = roz_dds_reader_open_kept(&jo->reader, &b->part, jo->name,
                                      &sensor_msgs_msg_dds__Joy__desc, &roz_dds_qos_robot_state,
                                      jo->sample, sizeof(joy_t), on_joy, jo, NULL, err, errlen);
    return rc;
}

/* ---- the command path's hooks (roz/port/dds.h says which thread runs each) ---------- */

static void encode_group(roz_ros2_bridge_t *b, roz_ros2_out_t *o, void *sample)
{
    const roz_ros2_group_t *g = &b->robot->groups[o->group];
    roz_ros2_cmd_t c = { &b->tx_joint[b->group_base[o->group]], g->n_slots, b->tx_sec,
                         b->tx_nanosec, ++o->sequence };
    b->robot->encode(b->vendor, o->group, &c, sample);
}

static int fill_group(void *ctx, void *sample, uint64_t now_ns)
{
    roz_ros2_out_t *o = ctx;
    (void)now_ns;
    encode_group(o->bridge, o, sample);
    return 1;
}

/* Every other group's topic from here, then the primary's sample (which the
 * writer publishes when this returns): one stamp for the pass. */
static int publish_all(roz_ros2_bridge_t *b, roz_ros2_out_t *o, void *sample)
{
    roz_ros2_stamp_now(&b->tx_sec, &b->tx_nanosec);
    for (uint16_t g = 0; g < b->robot->n_groups; g++) {
        if (g != o->group && reads(b, g))
            (void)roz_dds_writer_publish(&b->out[g].writer, fill_group, &b->out[g]);
    }
    encode_group(b, o, sample);
    return 1;
}

static void bridge_hold(void *port, const double *last, double *cmd)
{
    roz_ros2_bridge_t *b = port;
    roz__ros2_hold(b, b->tick_q, last, last != NULL ? b->shutdown_kd : b->startup_kd, cmd);
}

/* every topic's session, summed: any topic's peer restarting changes it */
static uint32_t bridge_rx_session(void *port)
{
    roz_ros2_bridge_t *b = port;
    uint32_t sum = 0;
    for (uint16_t t = 0; t < b->n_topics; t++) {
        if (reads(b, t))
            sum += atomic_load_explicit(&b->topic[t].rx_session, memory_order_acquire);
    }
    return sum;
}

static int bridge_send(void *port, void *sample, const double *cmd, const double *q, int hold)
{
    roz_ros2_bridge_t *b = port;
    roz__ros2_joints(b, cmd, q, b->tx_joint);
    /* the watchdog's hold is the controller's last command's, never that
     * of a hold the port made up; until the controller's first, the
     * start-up hold's (the measured positions) */
    for (uint16_t s = 0; s < b->n_slots; s++) {
        b->tx_meas_q[s] = q[s]; /* the latest finite one, NaN until there is one */
        if (hold && b->tx_ctrl)
            continue;
        b->tx_last_q[s] = b->tx_joint[s].q;
        b->tx_last_kp[s] = b->tx_joint[s].kp;
    }
    b->tx_ctrl |= !hold;
    return publish_all(b, &b->out[primary(b)], sample);
}

static int bridge_watchdog(void *port, void *sample);

/* The last command on the way out: the stop's hold (the humanoid's stop),
 * or damping where exit_stop chose it */
static int bridge_safe(void *port, void *sample)
{
    roz_ros2_bridge_t *b = port;
    if (!b->dds.exit_damping)
        return bridge_watchdog(port, sample);
    roz__ros2_damping(b, b->tx_last_q, b->shutdown_kd, 0, b->tx_joint);
    return publish_all(b, &b->out[primary(b)], sample);
}

/* The tick is silent: the stop's hold from the controller's last command
 * (roz_joints_hold_setpoint(): the hold gain, the torque kept within the
 * band of the measured position, a joint without a position command at its
 * measured position; test_pm01_watchdog_keeps_the_torque,
 * test_mujoco_stops_pm01); a slot without a hold (nothing measured, no
 * position command) gets no stiffness from roz__ros2_damping(). */
static int bridge_watchdog(void *port, void *sample)
{
    roz_ros2_bridge_t *b = port;
    double q[ROZ_ROS2_MAX_ROBOT_SLOTS];
    for (uint16_t s = 0; s < b->n_slots; s++) {
        int16_t k = b->slot_joint[s];
        q[s] = k >= 0 ? roz_joints_hold_setpoint(b->m, &b->joint[k], b->tx_last_q[s],
                                                 b->tx_last_kp[s], b->tx_meas_q[s])
                      : b->tx_last_q[s];
    }
    roz__ros2_damping(b, q, b->shutdown_kd, 1, b->tx_joint);
    return publish_all(b, &b->out[primary(b)], sample);
}

static const roz_dds_cmd_ops_t bridge_cmd_ops = {
    .hold = bridge_hold,
    .rx_session = bridge_rx_session,
    .refuse = NULL,
    .send = bridge_send,
    .safe = bridge_safe,
    .watchdog = bridge_watchdog,
};

/* ---- open -------------------------------------------------------------------------- */

static int setup_topic(roz_ros2_bridge_t *b, uint16_t t, const char *name, const void *type,
                       size_t size, uint16_t n_values, char *err, size_t errlen)
{
    roz_ros2_topic_t *tp = &b->topic[t];
    const roz_ros2_robot_t *r = b->robot;
    uint64_t period_ns = 1000000000u / b->m->control_rate_hz;
    int rc = ROZ_OK;

    if (type == NULL || size == 0 || size > sizeof tp->sample) {
        snprintf(err, errlen, "%s: topic %s: its type needs %lu bytes, the port has room for %lu",
                 r->port, name, (unsigned long)size, (unsigned long)sizeof tp->sample);
        return ROZ_EINVAL;
    }
    tp->bridge = b;
    tp->index = t;
    tp->name = name;
    tp->type = type;
    tp->size = size;
    tp->n_values = n_values;
    b->required |= 1u << t;
    roz_link_init(&tp->link, (uint64_t)b->peer_timeout_ms * 1000000u,
                  is_imu(b, t) || b->link_by_stamp ? ROZ_ROS2_STAMP_WINDOW_US : 0u);
    roz_link_shared_init(&tp->link_shared);
    roz_link_shared_publish(&tp->link_shared, &tp->link);
    roz_buffer_init(&tp->buf, tp->slots, (uint32_t)(n_values + ROZ_ROS2_STATE_META));
    roz_monitor_init(&tp->mon, name, period_ns, b->log, b->log_ctx);
    atomic_init(&tp->rx_session, 0u);
    atomic_init(&tp->fault_ack, 0u);
    atomic_init(&tp->said, 0u);
    tp->told = 0;
    for (unsigned k = 0; k < ROZ_ROS2_BAD_COUNT_; k++) {
        atomic_init(&tp->said_a[k], 0);
        atomic_init(&tp->said_b[k], 0);
    }
    ROZ_ATOMIC(uint64_t) *counters[] = { &tp->c_samples, &tp->c_malformed, &tp->c_full,
                                         &tp->c_fault, &tp->c_sessions };
    for (size_t i = 0; i < sizeof counters / sizeof counters[0]; i++)
        atomic_init(counters[i], 0u);
    /* the sample's sequences and strings, sized once */
    if (is_imu(b, t)) {
        std_msgs_msg_dds__Header_ *h = (void *)tp->sample;
        rc = roz_dds_string_reserve(&h->frame_id, FRAME_ID_ROOM);
    } else {
        rc = r->reserve(b->vendor, tp->sample, r->groups[t].n_slots);
    }
    if (rc != ROZ_OK)
        snprintf(err, errlen, "%s: topic %s: no room for its samples", r->port, name);
    return rc;
}

/* The Joy sample's sequences and frame_id, sized once: Cyclone fills them in
 * place. The sequences are unbounded on the wire (the .msg's, ros2_msgs.idl)
 * and hold ROZ_ROS2_JOY_MAX + 1 values here, not released: Cyclone 0.10's
 * deserializer fills a sequence of numbers that does not release up to its
 * _maximum and skips the rest, never growing it, so a Joy with more axes or
 * buttons than ROZ_ROS2_JOY_MAX arrives with ROZ_ROS2_JOY_MAX + 1 of them,
 * which on_joy() refuses and counts (a bound in the IDL would have Cyclone
 * drop it before roz sees it, counted nowhere). close() gives the buffers
 * back to Cyclone's free. */
static int reserve_joy(roz_ros2_bridge_t *b, char *err, size_t errlen)
{
    roz_ros2_op_topic_t *t = &b->op[OP_JOY];
    joy_t *j = (void *)t->sample;
    int rc = roz_dds_string_reserve(&j->header.frame_id, FRAME_ID_ROOM);
    if (rc == ROZ_OK)
        rc = roz_dds_seq_reserve(&j->axes, ROZ_ROS2_JOY_MAX + 1u, sizeof j->axes._buffer[0]);
    if (rc == ROZ_OK)
        rc = roz_dds_seq_reserve(&j->buttons, ROZ_ROS2_JOY_MAX + 1u,
                                 sizeof j->buttons._buffer[0]);
    j->axes._release = false;
    j->buttons._release = false;
    if (rc != ROZ_OK)
        snprintf(err, errlen, "%s: topic %s: no room for its samples", b->robot->port, t->name);
    return rc;
}

int roz_ros2_open(roz_ros2_bridge_t *b, const roz_ros2_robot_t *robot, void *vendor,
                  const roz_manifest_t *m, const roz_params_t *p, char *err, size_t errlen)
{
    roz_log_fn log = b->log != NULL ? b->log : log_stderr;
    void *log_ctx = b->log_ctx;
    roz_params_t params;
    int rc;

    if (b->open)
        roz_ros2_close(b);
    memset(b, 0, sizeof *b);
    b->log = log;
    b->log_ctx = log_ctx;
    b->robot = robot;
    b->vendor = vendor;
    if (m == NULL || roz_manifest_validate(m, NULL) != ROZ_OK) {
        snprintf(err, errlen, "%s: invalid manifest", robot->port);
        return ROZ_EINVAL;
    }
    b->m = m;
    for (uint16_t s = 0; s < ROZ_ROS2_MAX_ROBOT_SLOTS; s++)
        b->tick_q[s] = NAN; /* no position measured yet */
    rc = roz__ros2_bind(b, m, err, errlen) == ROZ_OK ? ROZ_OK : ROZ_EINVAL;
    if (rc == ROZ_OK) /* robot.toml's [hardware.params] first, then the caller's */
        rc = roz_params_merge(m, p, b->params, ROZ_ROS2_MAX_PARAMS, b->robot->port, &params,
                              err, errlen);
    if (rc == ROZ_OK)
        rc = roz__ros2_parse_params(b, &params, err, errlen, NULL, NULL);
    if (rc != ROZ_OK)
        return rc;

    /* the topics to read: the groups with a joint of the manifest, the IMU
     * when the manifest has an IMU channel */
    b->n_topics = (uint16_t)(robot->n_groups + 1u);
    size_t state_size = 0;
    const void *state_type = robot->state_type(vendor, &state_size);
    for (uint16_t g = 0; g < robot->n_groups && rc == ROZ_OK; g++) {
        int bound = 0;
        for (uint16_t j = 0; j < b->n_joints; j++)
            bound |= b->place[j].group == g;
        if (bound)
            rc = setup_topic(b, g, robot->groups[g].state_topic, state_type, state_size,
                             (uint16_t)(3u * robot->groups[g].n_slots), err, errlen);
    }
    int imu = 0;
    for (int k = 0; k < ROZ_IMU_VALUES; k++)
        imu |= b->imu[k] >= 0;
    if (rc == ROZ_OK && imu)
        rc = setup_topic(b, robot->n_groups, robot->imu_topic, robot->imu_type, robot->imu_size,
                         ROZ_IMU_VALUES, err, errlen);
    if (rc == ROZ_OK && b->op[OP_JOY].name[0] != '\0')
        rc = reserve_joy(b, err, errlen);
    b->open = 1; /* from here, close() frees what was made */
    if (rc != ROZ_OK) {
        roz_ros2_close(b);
        return rc;
    }

    uint64_t period_ns = b->dds.command_writer_period_us != 0
                             ? (uint64_t)b->dds.command_writer_period_us * 1000u
                             : 1000000000u / m->control_rate_hz;
    roz_monitor_init(&b->mon_tx, robot->port, period_ns, log, log_ctx);
    roz_dds_cmd_config_t cmd = { .m = m, .ops = &bridge_cmd_ops, .port = b,
                                 .writer = &b->out[primary(b)].writer, .slots = b->cmd_slots,
                                 .n_extra = ROZ_ROS2_MAX_ROBOT_SLOTS,
                                 .timeout_us = b->dds.command_timeout_us };
    roz_dds_cmd_init(&b->cmd, &cmd);
    atomic_init(&b->c_frames, 0u);
    atomic_init(&b->op_set, 0);
    for (int k = 0; k < 2; k++) {
        atomic_init(&b->op[k].c_samples, 0u);
        atomic_init(&b->op[k].c_refused, 0u);
        atomic_init(&b->op[k].c_handed, 0u);
        atomic_init(&b->op[k].c_oversized, 0u);
    }

    rc = roz_dds_participant_open(&b->part, b->dds.network_interface, b->dds.domain,
                                  &b->dds.cyclone_threads, log,
                                  log_ctx, err, errlen);
    for (uint16_t g = 0; g < robot->n_groups && rc == ROZ_OK; g++) {
        roz_ros2_out_t *o = &b->out[g];
        o->bridge = b;
        o->group = g;
        if (reads(b, g))
            rc = roz_dds_writer_open(&o->writer, &b->part, robot->groups[g].command_topic,
                                     robot->command_type, robot->command_qos, o->sample,
                                     robot->command_size, err, errlen);
    }
    if (rc == ROZ_OK)
        rc = roz_dds_cmd_attach(&b->cmd, b->dds.command_writer_spin_us);
    if (rc != ROZ_OK)
        roz_ros2_close(b);
    return rc;
}

/* ---- ops ---------------------------------------------------------------------------- */

int roz_ros2_activate(void *self)
{
    roz_ros2_bridge_t *b = self;
    const roz_ros2_robot_t *r;
    char err[240];
    int rc = ROZ_OK;

    if (!b->open)
        return ROZ_ESTATE;
    if (b->active)
        return ROZ_OK;
    r = b->robot;
    for (uint16_t t = 0; t < b->n_topics && rc == ROZ_OK; t++) {
        roz_ros2_topic_t *tp = &b->topic[t];
        if (!reads(b, t))
            continue;
        rc = roz_dds_reader_open_kept(&tp->reader, &b->part, tp->name, tp->type, r->state_qos,
                                      tp->sample, tp->size, on_sample, tp,
                                      b->dds.enable_monitor ? &tp->mon : NULL, err, sizeof err);
    }
    if (rc == ROZ_OK)
        rc = open_operator(b, err, sizeof err);
    if (rc == ROZ_OK) {
        roz_dds_writer_t *w = &b->out[primary(b)].writer;
        roz_dds_writer_set_thread(w, &b->dds.writer_thread);
        rc = roz_dds_cmd_start(&b->cmd, b->dds.command_writer_period_us,
                               b->dds.enable_monitor ? &b->mon_tx : NULL);
        if (rc != ROZ_OK && roz_dds_writer_thread_error(w)[0] != '\0') {
            snprintf(err, sizeof err, "%s: %s", b->robot->port, roz_dds_writer_thread_error(w));
            b->log(b->log_ctx, ROZ_LOG_ERROR, err);
        }
    } else {
        b->log(b->log_ctx, ROZ_LOG_ERROR, err);
    }
    if (rc != ROZ_OK) {
        for (uint16_t t = 0; t < b->n_topics; t++)
            roz_dds_reader_close(&b->topic[t].reader);
        for (int k = 0; k < 2; k++)
            roz_dds_reader_close(&b->op[k].reader);
        return rc;
    }
    b->active = 1;
    return ROZ_OK;
}

/* The manifest's state from the staged topics, and each slot's position. */
static void assemble(roz_ros2_bridge_t *b)
{
    const roz_ros2_robot_t *r = b->robot;
    for (uint16_t g = 0; g < r->n_groups; g++) {
        if (!reads(b, g))
            continue;
        uint16_t n = r->groups[g].n_slots;
        /* the positions the command path falls back on: the latest finite
         * one of each slot (NaN until the robot reported one), never what
         * the robot sent when it is not a number (test_x2_nonfinite_state_
         * never_on_the_wire) */
        for (uint16_t s = 0; s < n; s++) {
            double q = b->topic[g].staged[s];
            if (isfinite(q))
                b->tick_q[b->group_base[g] + s] = q;
        }
    }
    for (uint16_t k = 0; k < b->n_joints; k++) {
        const roz_joint_channels_t *j = &b->joint[k];
        const roz_ros2_place_t *at = &b->place[k];
        const double *v = b->topic[at->group].staged;
        uint16_t n = r->groups[at->group].n_slots;
        if (j->q_state >= 0)
            b->tick_frame[j->q_state] = v[at->slot];
        if (j->dq_state >= 0)
            b->tick_frame[j->dq_state] = v[n + at->slot];
        if (j->tau_state >= 0)
            b->tick_frame[j->tau_state] = v[2u * n + at->slot];
    }
    const double *imu = b->topic[r->n_groups].staged;
    for (int k = 0; k < ROZ_IMU_VALUES; k++) {
        if (b->imu[k] >= 0)
            b->tick_frame[b->imu[k]] = imu[k];
    }
}

/* The first fault a topic reported since the last fresh frame, into
 * tick_fault (0: none); each topic's is cleared for the next frame. */
static int robot_fault(roz_ros2_bridge_t *b)
{
    const roz_ros2_robot_t *r = b->robot;
    int found = 0;
    for (uint16_t g = 0; g < r->n_groups; g++) {
        roz_ros2_topic_t *tp = &b->topic[g];
        uint32_t kind = tp->tick_fault_kind;
        if (!reads(b, g) || kind == 0)
            continue;
        tp->tick_fault_kind = 0;
        if (found)
            continue;
        int32_t slot = tp->tick_fault_slot;
        b->tick_fault.what = slot >= 0 && slot < (int32_t)r->groups[g].n_slots
                                 ? r->groups[g].slots[slot]
                                 : r->groups[g].name;
        b->tick_fault.kind = r->fault_kinds != NULL ? r->fault_kinds[kind - 1u] : "fault";
        b->tick_fault.code = tp->tick_fault_code;
        b->tick_fault.limit = 0;
        found = 1;
    }
    return found;
}

/* A staged frame's fault: kept as the topic's first since the last fresh
 * frame, and acknowledged to the receive thread, which stops holding it. */
static void take_fault(roz_ros2_topic_t *tp)
{
    const double *meta = tp->staged + tp->n_values;
    uint32_t kind = (uint32_t)meta[M_FAULT_KIND];
    if (kind != 0 && tp->tick_fault_kind == 0) {
        tp->tick_fault_kind = kind;
        tp->tick_fault_slot = (int32_t)meta[M_FAULT_SLOT];
        tp->tick_fault_code = (uint32_t)meta[M_FAULT_CODE];
    }
    atomic_store_explicit(&tp->fault_ack, (uint32_t)meta[M_FAULT_SERIAL], memory_order_release);
}

static int read_frame(roz_ros2_bridge_t *b, double *state, size_t n)
{
    int restarted = 0;

    b->tick_fault.what = NULL; /* fault() speaks of this read only (roz/port.h) */
    for (uint16_t t = 0; t < b->n_topics; t++) {
        roz_ros2_topic_t *tp = &b->topic[t];
        roz_buffer_frame_t f;
        if (!reads(b, t) || roz_buffer_read(&tp->buf, &f) != 1)
            continue;
        memcpy(tp->staged, f.values, (tp->n_values + ROZ_ROS2_STATE_META) * sizeof f.values[0]);
        take_fault(tp);
        uint32_t session = (uint32_t)tp->staged[tp->n_values + M_SESSION];
        if (session != tp->tick_session) {
            restarted |= tp->tick_session != 0;
            tp->tick_session = session;
        }
        b->delivered |= 1u << t;
    }
    if (!b->tick_has_state) {
        if ((b->delivered & b->required) != b->required)
            return ROZ_ENOENT; /* not every topic yet */
        restarted = 0;         /* a peer that restarted before the first frame: its first */
    }
    if (restarted) {
        /* a restarted robot: its start-up layers begin again */
        assemble(b);
        b->delivered = 0;
        b->tick_robot++;
        memcpy(state, b->tick_frame, n * sizeof state[0]);
        return ROZ_ELINK;
    }
    if ((b->delivered & b->required) != b->required) {
        memcpy(state, b->tick_frame, n * sizeof state[0]);
        return 0;
    }
    b->delivered = 0;
    assemble(b);
    if (!b->tick_has_state) {
        b->tick_has_state = 1;
        b->tick_robot++;
    }
    bump(&b->c_frames);
    memcpy(state, b->tick_frame, n * sizeof state[0]);
    return robot_fault(b) ? ROZ_EROBOT : 1;
}

int roz_ros2_read(void *self, double *state, size_t n)
{
    roz_ros2_bridge_t *b = self;

    if (!b->open || n != b->m->n_states)
        return ROZ_EINVAL;
    return roz_dds_cmd_report(&b->cmd, read_frame(b, state, n), &b->tick_fault);
}

int roz_ros2_write(void *self, const double *cmd, size_t n)
{
    roz_ros2_bridge_t *b = self;

    if (!b->open)
        return ROZ_EINVAL;
    /* the session every topic's frames came from, summed (bridge_rx_session()) */
    uint32_t sessions = 0;
    for (uint16_t t = 0; t < b->n_topics; t++) {
        if (reads(b, t))
            sessions += b->topic[t].tick_session;
    }
    roz_dds_cmd_tick_t t = { .has_state = b->tick_has_state, .robot = b->tick_robot,
                             .session = sessions, .extra = b->tick_q };
    return roz_dds_cmd_write(&b->cmd, cmd, n, &t);
}

int roz_ros2_deactivate(void *self)
{
    roz_ros2_bridge_t *b = self;

    if (!b->active)
        return ROZ_OK;
    roz_ros2_out_t *o = &b->out[primary(b)];
    /* the last command: the exit stop; the primary's pass publishes every other
     * group's too, and they are flushed as the primary's is */
    if (roz_dds_cmd_stop(&b->cmd) == 1) {
        for (uint16_t g = 0; g < b->robot->n_groups; g++) {
            if (g != o->group && reads(b, g))
                (void)roz_dds_writer_flush(&b->out[g].writer, ROZ_DDS_SHUTDOWN_FLUSH_MS);
        }
    }
    for (uint16_t t = 0; t < b->n_topics; t++)
        roz_dds_reader_close(&b->topic[t].reader);
    for (int k = 0; k < 2; k++)
        roz_dds_reader_close(&b->op[k].reader);
    b->active = 0;
    return ROZ_OK;
}

void roz_ros2_close(void *self)
{
    roz_ros2_bridge_t *b = self;

    if (!b->open)
        return;
    (void)roz_ros2_deactivate(b);
    for (uint16_t g = 0; g < ROZ_ROS2_MAX_GROUPS; g++)
        roz_dds_writer_close(&b->out[g].writer);
    roz_dds_participant_close(&b->part);
    for (uint16_t t = 0; t < b->n_topics; t++) {
        roz_ros2_topic_t *tp = &b->topic[t];
        if (reads(b, t))
            roz_dds_sample_free(tp->sample, sizeof tp->sample, tp->type);
    }
    joy_t *j = (void *)b->op[OP_JOY].sample;
    j->axes._release = j->axes._buffer != NULL; /* reserve_joy()'s, Cyclone's to free */
    j->buttons._release = j->buttons._buffer != NULL;
    roz_dds_sample_free(b->op[OP_JOY].sample, sizeof b->op[OP_JOY].sample,
                        &sensor_msgs_msg_dds__Joy__desc);
    b->open = 0;
}

int roz_ros2_fault(void *self, roz_port_fault_t *out)
{
    roz_ros2_bridge_t *b = self;
    *out = b->tick_fault;
    return ROZ_OK;
}

/* ---- public ------------------------------------------------------------------------ */

int roz_ros2_topic_link(const roz_ros2_bridge_t *b, uint16_t t, roz_link_t *out)
{
    if (t >= b->n_topics || !reads(b, t)) {
        memset(out, 0, sizeof *out);
        return ROZ_EINVAL;
    }
    (void)roz_link_shared_read(&b->topic[t].link_shared, out);
    return ROZ_OK;
}

void roz_ros2_link(const roz_ros2_bridge_t *b, roz_link_t *out)
{
    int first = 1;
    memset(out, 0, sizeof *out);
    out->alive = 1;
    for (uint16_t t = 0; t < b->n_topics; t++) {
        roz_link_t l;
        if (roz_ros2_topic_link(b, t, &l) != ROZ_OK)
            continue;
        if (first) {
            out->lost_after_ns = l.lost_after_ns;
            out->window = l.window;
            out->last_seq = l.last_seq;
            out->last_ns = l.last_ns;
            first = 0;
        }
        out->alive &= l.alive;
        out->accepted += l.accepted;
        out->crc_errors += l.crc_errors;
        out->replays += l.replays;
        out->restarts += l.restarts;
        out->returns += l.returns;
        /* a stamp's gaps are microseconds, not frames: only sequence numbers
         * tell frames missing */
        if (!is_imu(b, t) && !b->link_by_stamp)
            out->missing += l.missing;
    }
    if (first)
        out->alive = 0;
}

int roz_ros2_link_counters(const void *self, roz_port_link_counters_t *out)
{
    const roz_ros2_bridge_t *b = self;
    roz_ros2_counters_t c;
    roz_link_t l;
    uint64_t malformed = 0;
    roz_ros2_link(b, &l);
    roz_ros2_counters(b, &c);
    for (uint16_t t = 0; t < c.n_topics; t++)
        malformed += c.topic[t].malformed;
    roz_link_port_counters(&l, malformed, out);
    return ROZ_OK;
}

void roz_ros2_counters(const roz_ros2_bridge_t *b, roz_ros2_counters_t *out)
{
    memset(out, 0, sizeof *out);
    out->n_topics = b->n_topics;
    for (uint16_t t = 0; t < b->n_topics; t++) {
        const roz_ros2_topic_t *tp = &b->topic[t];
        out->topic[t].samples = load(&tp->c_samples);
        out->topic[t].malformed = load(&tp->c_malformed);
        out->topic[t].full = load(&tp->c_full);
        out->topic[t].fault_frames = load(&tp->c_fault);
        out->topic[t].sessions = load(&tp->c_sessions);
    }
    const roz_dds_writer_t *w = &b->out[primary(b)].writer;
    out->frames = load(&b->c_frames);
    out->writes = roz_dds_cmd_count(&b->cmd, ROZ_DDS_CMD_WRITES);
    out->writes_withheld = roz_dds_cmd_count(&b->cmd, ROZ_DDS_CMD_WITHHELD);
    out->holds = roz_dds_cmd_count(&b->cmd, ROZ_DDS_CMD_HOLDS);
    out->clamped = roz_dds_cmd_count(&b->cmd, ROZ_DDS_CMD_CLAMPED);
    /* done before passes: a pass that ends between the two loads shows as
     * open, never the other way round */
    out->writer_done = load(&w->done);
    out->writer_passes = load(&w->passes);
    out->published = load(&w->published);
    for (uint16_t g = 0; g < b->robot->n_groups; g++)
        out->publish_errors += load(&b->out[g].writer.errors);
    out->stale_session = roz_dds_cmd_count(&b->cmd, ROZ_DDS_CMD_STALE);
    out->handled_seq = roz_dds_cmd_count(&b->cmd, ROZ_DDS_CMD_HANDLED_SEQ);
    out->written_seq = roz_dds_cmd_count(&b->cmd, ROZ_DDS_CMD_WRITTEN_SEQ);
    out->command_timeouts = roz_dds_cmd_timeouts(&b->cmd);
    out->safe_published = roz_dds_cmd_count(&b->cmd, ROZ_DDS_CMD_SAFE);
    for (int k = 0; k < 2; k++) {
        out->operator_samples[k] = load(&b->op[k].c_samples);
        out->operator_refused[k] = load(&b->op[k].c_refused);
        out->operator_handed[k] = load(&b->op[k].c_handed);
    }
    out->operator_oversized = load(&b->op[OP_JOY].c_oversized);
}

void roz_ros2_matched(const roz_ros2_bridge_t *b, uint32_t *cmd_readers, uint32_t *state_writers)
{
    uint32_t readers = UINT32_MAX, writers = UINT32_MAX;
    for (uint16_t g = 0; g < b->robot->n_groups; g++) {
        if (!reads(b, g))
            continue;
        uint32_t k = roz_dds_writer_matched(&b->out[g].writer);
        readers = k < readers ? k : readers;
    }
    for (uint16_t t = 0; t < b->n_topics; t++) {
        if (!reads(b, t))
            continue;
        uint32_t k = roz_dds_reader_matched(&b->topic[t].reader);
        writers = k < writers ? k : writers;
    }
    *cmd_readers = readers == UINT32_MAX ? 0 : readers;
    *state_writers = writers == UINT32_MAX ? 0 : writers;
}

const roz_ros2_robot_t *roz_ros2_robot(const roz_ros2_bridge_t *b)
{
    return b->robot;
}

const roz_dds_params_t *roz_ros2_dds_params(const roz_ros2_bridge_t *b)
{
    return &b->dds;
}

const roz_dds_participant_t *roz_ros2_participant(const roz_ros2_bridge_t *b)
{
    return &b->part;
}

const roz_monitor_t *roz_ros2_writer_monitor(const roz_ros2_bridge_t *b)
{
    return &b->mon_tx;
}

const roz_monitor_t *roz_ros2_topic_monitor(const roz_ros2_bridge_t *b, uint16_t t)
{
    return t < b->n_topics && reads(b, t) ? &b->topic[t].mon : NULL;
}

roz_port_t roz_ros2_port(const roz_port_ops_t *ops, roz_ros2_bridge_t *b,
                         const roz_port_layout_t *caller, size_t bytes, size_t size,
                         roz_log_fn log, void *log_ctx)
{
    roz_port_t p = roz_port_make(ops, b, caller, bytes, size);
    if (p.self == NULL)
        return p; /* misbuilt: nothing written to the instance */
    b->open = 0;
    b->log = log;
    b->log_ctx = log_ctx;
    return p;
}
