/* SPDX-License-Identifier: Apache-2.0 */
/* fake_ros2: a stand-in EngineAI PM01 or AgiBot X2 speaking its ROS 2
 * topics on Cyclone DDS, for roz's tests, written from the robots' topic and
 * message descriptions alone (README.md), never from the ports. It
 * publishes each joint group's state and the IMU when told to (or every
 * --period-us), receives every group's commands and keeps the last one; a
 * test drives it over stdin/stdout, one request line in, one reply out.
 *
 * Threads: main (requests, publishing), the periodic publisher (with
 * --period-us), Cyclone's (the command listeners). Lock order: pub_lock
 * before lock; dds_write is never called under lock, which the listeners
 * take. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <dds/dds.h>

#include "fake_dds.h"
#include "fake_reply.h"
#include "robots.h"
#include "ros2_robot.h"

#define MIN_PERIOD_US 100u
#define MAX_PERIOD_US 1000000u
#define REMATCH_POLLS 5000 /* ms a restarted writer may take to meet the old readers */
#define NAME_MAX_LEN 63
#define LINE_MAX_LEN 1024
#define CLOCK_START_NS 1700000000000000000LL /* the robot's clock at start: 2023-11 */
#define CLOCK_STEP_NS 1000000LL               /* 1 ms from one sample to the next */
#define RESTART_BACK_NS 10000000000LL         /* a rebooted robot's clock: 10 s back */
#define JOY_MAX 64 /* a Joy's axes and buttons the fake can send: beyond any port's bound */

/* ---- the model ------------------------------------------------------------- */

typedef struct {
    double   q, dq, tau;
    uint16_t error_code;
    char     name[NAME_MAX_LEN + 1]; /* "": the robot's own */
    int      unnamed;                /* an empty name on the wire */
} fjoint_t;

typedef struct {
    fjoint_t j[FAKE_MAX_SLOTS];
    uint32_t length; /* joints a sample carries */
    uint8_t  error;  /* DomainErrorState (X2) */
    uint32_t seq;    /* header sequence (X2) */
    int64_t  stamp_ns;
    int      raw;    /* the stamp is sec, nsec below, as asked ("stamp") */
    int32_t  sec;
    uint32_t nsec;
} gmodel_t;

typedef struct {
    uint32_t sec, nanosec, seq;
    char     frame_id[NAME_MAX_LEN + 1];
    unsigned ppt; /* parallel_parser_type (PM01) */
    uint32_t n;       /* joints: the longest array (PM01), the joints' length (X2) */
    uint32_t min_len; /* the shortest array (PM01); n (X2) */
    char     name[FAKE_MAX_SLOTS][NAME_MAX_LEN + 1];
    double   q[FAKE_MAX_SLOTS], dq[FAKE_MAX_SLOTS], tau[FAKE_MAX_SLOTS];
    double   kp[FAKE_MAX_SLOTS], kd[FAKE_MAX_SLOTS], extra[FAKE_MAX_SLOTS];
} fcmd_t;

typedef struct {
    const fake_group_t *g;
    dds_entity_t        state_topic, state_writer, cmd_topic, cmd_reader;
    /* pub_lock */
    gmodel_t            last;      /* the last sample sent, for a replay */
    int                 have_last;
    int                 muted;
    /* lock */
    gmodel_t            model;
    uint64_t            commands;
    int                 have_cmd;
    fcmd_t              cmd;
} fgroup_t;

typedef struct {
    const fake_robot_t *robot;
    int                 docs_layout;
    int                 typeinfo;
    uint32_t            period_us;
    dds_entity_t        participant;
    const dds_topic_descriptor_t *state_desc, *cmd_desc, *imu_desc;
    fgroup_t            group[FAKE_MAX_GROUPS];
    dds_entity_t        imu_topic, imu_writer;
    dds_qos_t          *state_qos;

    pthread_mutex_t     pub_lock;
    int64_t             clock_ns;    /* the robot's clock: the stamps */
    int                 raw_pending; /* topics (a bit each) whose next sample carries raw */
    int32_t             raw_sec;     /* the stamp asked for ("stamp") */
    uint32_t            raw_nsec;
    double              imu_last[10];
    int64_t             imu_last_stamp;
    int                 imu_have_last, imu_muted;

    pthread_mutex_t     lock;
    pthread_cond_t      changed;
    double              imu[10];     /* qx qy qz qw gx gy gz ax ay az */
    int                 stopping;

    pthread_t           period_thread;
    int                 period_running;

    /* the operator: a ROS 2 teleop node and a joy node on this host
     * (main thread only) */
    const char         *cmd_vel_topic, *joy_topic; /* DDS names */
    const dds_topic_descriptor_t *twist_desc, *joy_desc;
    dds_entity_t        twist_writer, joy_writer;
    uint32_t            joy_axes, joy_buttons; /* the lengths sent */
    float               joy_axis[JOY_MAX];
    int32_t             joy_button[JOY_MAX];
} fake_t;

static fake_t fake;

/* A reply line being built: what line_add() appends, cut at its size. */
typedef struct {
    char   s[256];
    size_t n;
} line_t;

__attribute__((format(printf, 2, 3)))
static void line_add(line_t *l, const char *fmt, ...)
{
    if (l->n >= sizeof l->s)
        return;
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(l->s + l->n, sizeof l->s - l->n, fmt, ap);
    va_end(ap);
    if (n > 0)
        l->n += (size_t)n;
}

/* ---- types and QoS ----------------------------------------------------------- */

/* A descriptor under another type name and/or without XTypes type
 * information (as rmw_cyclonedds registers its types): matched by name. */
static const dds_topic_descriptor_t *retype(const dds_topic_descriptor_t *d, const char *name,
                                            int typeinfo)
{
    if (name == NULL && typeinfo)
        return d;
    const struct dds_type_meta_ser none = { NULL, 0 };
    const dds_topic_descriptor_t copy = {
        .m_size = d->m_size,
        .m_align = d->m_align,
        .m_flagset = typeinfo ? d->m_flagset : d->m_flagset & ~DDS_TOPIC_XTYPES_METADATA,
        .m_nkeys = d->m_nkeys,
        .m_typename = name != NULL ? name : d->m_typename,
        .m_keys = d->m_keys,
        .m_nops = d->m_nops,
        .m_ops = d->m_ops,
        .m_meta = d->m_meta,
        .type_information = typeinfo ? d->type_information : none,
        .type_mapping = typeinfo ? d->type_mapping : none,
        .restrict_data_representation = d->restrict_data_representation,
    };
    dds_topic_descriptor_t *c = malloc(sizeof *c);
    if (c != NULL)
        memcpy(c, &copy, sizeof copy);
    return c;
}

static void choose_types(fake_t *f)
{
    if (f->robot->kind == FAKE_PM01) {
        f->state_desc = retype(&interface_protocol_msg_dds__JointState__desc, NULL, f->typeinfo);
        f->cmd_desc = retype(&interface_protocol_msg_dds__JointCommand__desc, NULL, f->typeinfo);
        f->imu_desc = retype(&interface_protocol_msg_dds__ImuInfo__desc, NULL, f->typeinfo);
    } else {
        /* the documentation's JointState under the type name the SDK's has
         * (no type information: it could not be the SDK's) */
        f->state_desc = f->docs_layout
                            ? retype(&fake_x2_docs_msg_dds__JointStateArray__desc,
                                     "aimdk_msgs::msg::dds_::JointStateArray_", 0)
                            : retype(&aimdk_msgs_msg_dds__JointStateArray__desc, NULL, f->typeinfo);
        f->cmd_desc = retype(&aimdk_msgs_msg_dds__JointCommandArray__desc, NULL, f->typeinfo);
        f->imu_desc = retype(&sensor_msgs_msg_dds__Imu__desc, NULL, f->typeinfo);
    }
}

/* The robots' own QoS: the PM01's hardware node publishes KEEP_LAST 3,
 * BEST_EFFORT; the X2's documentation gives its state topics
 * TRANSIENT_LOCAL. Commands are read BEST_EFFORT (matches any writer),
 * KEEP_ALL (every sample counted). */
static dds_qos_t *state_qos(const fake_t *f)
{
    dds_qos_t *q = dds_create_qos();
    dds_qset_reliability(q, DDS_RELIABILITY_BEST_EFFORT, 0);
    if (f->robot->kind == FAKE_PM01) {
        dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 3);
        dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
    } else {
        dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 5);
        dds_qset_durability(q, DDS_DURABILITY_TRANSIENT_LOCAL);
    }
    return q;
}

/* ---- time ---------------------------------------------------------------------- */

static void stamp_of(int64_t ns, int32_t *sec, uint32_t *nanosec)
{
    *sec = (int32_t)(ns / 1000000000LL);
    *nanosec = (uint32_t)(ns % 1000000000LL);
}

static void sleep_ms(unsigned ms)
{
    struct timespec ts = { (time_t)(ms / 1000u), (long)(ms % 1000u) * 1000000L };
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR)
        ;
}

/* ---- state samples (pub_lock held) ------------------------------------------------ */

static const char *joint_name(const fgroup_t *g, const gmodel_t *m, uint32_t i)
{
    if (m->j[i].unnamed)
        return "";
    if (m->j[i].name[0] != '\0')
        return m->j[i].name;
    return i < g->g->n_joints ? g->g->joints[i] : "";
}

/* Joint @p i of @p m in @p jt, of either X2 layout: its name, position,
 * velocity and effort. */
#define X2_JOINT(jt, g, m, i)                                        \
    do {                                                             \
        (jt).name = (char *)(uintptr_t)joint_name((g), (m), (i));    \
        (jt).position = (m)->j[(i)].q;                               \
        (jt).velocity = (m)->j[(i)].dq;                              \
        (jt).effort = (m)->j[(i)].tau;                               \
    } while (0)

/* @p s, a JointStateArray of either X2 layout: header @p h, @p m's error
 * and its joints @p j (not released by the writer). */
#define X2_JOINT_ARRAY(s, h, m, j)                                    \
    do {                                                             \
        (s).header = (h);                                            \
        (s).state.value = (m)->error;                                \
        (s).joints._buffer = (j);                                    \
        (s).joints._length = (s).joints._maximum = (m)->length;      \
        (s).joints._release = false;                                 \
    } while (0)

static int write_group(fake_t *f, fgroup_t *g, const gmodel_t *m)
{
    static char empty[1];
    int32_t sec = m->sec;
    uint32_t nsec = m->nsec;
    if (!m->raw)
        stamp_of(m->stamp_ns, &sec, &nsec);
    if (f->robot->kind == FAKE_PM01) {
        double q[FAKE_MAX_SLOTS], dq[FAKE_MAX_SLOTS], tau[FAKE_MAX_SLOTS];
        interface_protocol_msg_dds__JointState_ s;
        memset(&s, 0, sizeof s);
        for (uint32_t i = 0; i < m->length; i++) {
            q[i] = m->j[i].q;
            dq[i] = m->j[i].dq;
            tau[i] = m->j[i].tau;
        }
        s.header.stamp.sec = sec;
        s.header.stamp.nanosec = nsec;
        s.header.frame_id = empty;
        s.position = (dds_sequence_double){ m->length, m->length, q, false };
        s.velocity = (dds_sequence_double){ m->length, m->length, dq, false };
        s.torque = (dds_sequence_double){ m->length, m->length, tau, false };
        return dds_write(g->state_writer, &s);
    }
    aimdk_msgs_msg_dds__MessageHeader_ h;
    memset(&h, 0, sizeof h);
    h.stamp.sec = sec;
    h.stamp.nanosec = nsec;
    h.frame_id = empty;
    h.sequence = m->seq;
    h.meas_stamp = h.stamp;
    if (f->docs_layout) {
        fake_x2_docs_msg_dds__JointState_ j[FAKE_MAX_SLOTS];
        fake_x2_docs_msg_dds__JointStateArray_ s;
        memset(j, 0, sizeof j);
        for (uint32_t i = 0; i < m->length; i++) {
            X2_JOINT(j[i], g, m, i);
            j[i].coil_temp = 41;
            j[i].motor_temp = 38;
            j[i].motor_vol = 48;
        }
        X2_JOINT_ARRAY(s, h, m, j);
        return dds_write(g->state_writer, &s);
    }
    aimdk_msgs_msg_dds__JointState_ j[FAKE_MAX_SLOTS];
    aimdk_msgs_msg_dds__JointStateArray_ s;
    memset(j, 0, sizeof j);
    for (uint32_t i = 0; i < m->length; i++) {
        X2_JOINT(j[i], g, m, i);
        j[i].error_code = m->j[i].error_code;
    }
    X2_JOINT_ARRAY(s, h, m, j);
    return dds_write(g->state_writer, &s);
}

/* Fills @p s, an IMU message of either robot's type whose orientation is
 * its field @p quat: stamped @p sec, @p nsec, frame id "", the orientation,
 * rates and accelerations of @p v (qx qy qz qw gx gy gz ax ay az). */
#define FILL_IMU(s, quat, sec, nsec, v)                                                  \
    do {                                                                                 \
        static char empty_[1];                                                           \
        memset(&(s), 0, sizeof(s));                                                      \
        (s).header.stamp.sec = (sec);                                                    \
        (s).header.stamp.nanosec = (nsec);                                               \
        (s).header.frame_id = empty_;                                                    \
        (s).quat = (geometry_msgs_msg_dds__Quaternion_){ (v)[0], (v)[1], (v)[2], (v)[3] }; \
        (s).angular_velocity = (geometry_msgs_msg_dds__Vector3_){ (v)[4], (v)[5], (v)[6] }; \
        (s).linear_acceleration =                                                        \
            (geometry_msgs_msg_dds__Vector3_){ (v)[7], (v)[8], (v)[9] };                 \
    } while (0)

static int write_imu(fake_t *f, const double *v, int64_t stamp_ns, int raw)
{
    int32_t sec = f->raw_sec;
    uint32_t nsec = f->raw_nsec;
    if (!raw)
        stamp_of(stamp_ns, &sec, &nsec);
    if (f->robot->kind == FAKE_PM01) {
        interface_protocol_msg_dds__ImuInfo_ s;
        FILL_IMU(s, quaternion, sec, nsec, v);
        return dds_write(f->imu_writer, &s);
    }
    sensor_msgs_msg_dds__Imu_ s;
    FILL_IMU(s, orientation, sec, nsec, v);
    return dds_write(f->imu_writer, &s);
}

/* A new sample on group g (g == n_groups: the IMU): the next stamp, the
 * next sequence. pub_lock held. */
static int send_new(fake_t *f, uint16_t g)
{
    int raw = (f->raw_pending >> g) & 1;
    f->raw_pending &= ~(1 << g);
    f->clock_ns += CLOCK_STEP_NS;
    if (g == f->robot->n_groups) {
        double v[10];
        pthread_mutex_lock(&f->lock);
        memcpy(v, f->imu, sizeof v);
        pthread_mutex_unlock(&f->lock);
        memcpy(f->imu_last, v, sizeof v);
        f->imu_last_stamp = f->clock_ns;
        f->imu_have_last = !raw;
        return write_imu(f, v, f->clock_ns, raw);
    }
    fgroup_t *gr = &f->group[g];
    pthread_mutex_lock(&f->lock);
    gmodel_t m = gr->model;
    gr->model.seq++;
    pthread_mutex_unlock(&f->lock);
    m.stamp_ns = f->clock_ns;
    m.raw = raw;
    m.sec = f->raw_sec;
    m.nsec = f->raw_nsec;
    gr->last = m;
    gr->have_last = 1;
    return write_group(f, gr, &m);
}

static int send_replay(fake_t *f, uint16_t g)
{
    if (g == f->robot->n_groups)
        return f->imu_have_last ? write_imu(f, f->imu_last, f->imu_last_stamp, 0) : -1;
    fgroup_t *gr = &f->group[g];
    return gr->have_last ? write_group(f, gr, &gr->last) : -1;
}

/* ---- commands (Cyclone's thread) ---------------------------------------------------- */

static void copy_name(char *dst, const char *src)
{
    snprintf(dst, NAME_MAX_LEN + 1, "%s", src != NULL && src[0] != '\0' ? src : "-");
}

static double at(const dds_sequence_double *s, uint32_t i)
{
    return i < s->_length ? s->_buffer[i] : 0.0;
}

static void take_command(fake_t *f, fgroup_t *g, const void *sample)
{
    fcmd_t c;
    memset(&c, 0, sizeof c);
    if (f->robot->kind == FAKE_PM01) {
        const interface_protocol_msg_dds__JointCommand_ *s = sample;
        c.sec = (uint32_t)s->header.stamp.sec;
        c.nanosec = s->header.stamp.nanosec;
        copy_name(c.frame_id, s->header.frame_id);
        c.ppt = s->parallel_parser_type;
        /* the longest array; a shorter one shows as its length in the reply */
        const dds_sequence_double *arr[6] = { &s->position, &s->velocity,
                                              &s->feed_forward_torque, &s->stiffness,
                                              &s->damping, &s->torque };
        uint32_t n = 0, shortest = UINT32_MAX;
        for (int k = 0; k < 6; k++) {
            n = arr[k]->_length > n ? arr[k]->_length : n;
            shortest = arr[k]->_length < shortest ? arr[k]->_length : shortest;
        }
        c.n = n > FAKE_MAX_SLOTS ? FAKE_MAX_SLOTS : n;
        c.min_len = shortest;
        for (uint32_t i = 0; i < c.n; i++) {
            copy_name(c.name[i], NULL);
            c.q[i] = at(&s->position, i);
            c.dq[i] = at(&s->velocity, i);
            c.tau[i] = at(&s->feed_forward_torque, i);
            c.kp[i] = at(&s->stiffness, i);
            c.kd[i] = at(&s->damping, i);
            c.extra[i] = at(&s->torque, i);
        }
    } else {
        const aimdk_msgs_msg_dds__JointCommandArray_ *s = sample;
        c.sec = (uint32_t)s->header.stamp.sec;
        c.nanosec = s->header.stamp.nanosec;
        copy_name(c.frame_id, s->header.frame_id);
        c.seq = s->header.sequence;
        c.n = s->joints._length > FAKE_MAX_SLOTS ? FAKE_MAX_SLOTS : s->joints._length;
        c.min_len = s->joints._length;
        for (uint32_t i = 0; i < c.n; i++) {
            const aimdk_msgs_msg_dds__JointCommand_ *j = &s->joints._buffer[i];
            copy_name(c.name[i], j->name);
            c.q[i] = j->position;
            c.dq[i] = j->velocity;
            c.tau[i] = j->effort;
            c.kp[i] = j->stiffness;
            c.kd[i] = j->damping;
        }
    }
    pthread_mutex_lock(&f->lock);
    g->cmd = c;
    g->have_cmd = 1;
    g->commands++;
    pthread_cond_broadcast(&f->changed);
    pthread_mutex_unlock(&f->lock);
}

static void on_command(dds_entity_t reader, void *arg)
{
    fgroup_t *g = arg;
    for (;;) {
        void *samples[8] = { NULL };
        dds_sample_info_t info[8];
        dds_return_t n = dds_take(reader, samples, info, 8, 8);
        if (n <= 0)
            return;
        for (int i = 0; i < n; i++) {
            if (info[i].valid_data)
                take_command(&fake, g, samples[i]);
        }
        (void)dds_return_loan(reader, samples, n);
    }
}

/* ---- DDS entities ---------------------------------------------------------------- */

static int open_dds(fake_t *f, uint32_t domain)
{
    f->participant = fake_dds_participant(domain, "fake_ros2");
    if (f->participant < 0)
        return -1;
    choose_types(f);
    if (f->state_desc == NULL || f->cmd_desc == NULL || f->imu_desc == NULL)
        return -1;
    f->state_qos = state_qos(f);
    dds_qos_t *cq = dds_create_qos();
    dds_qset_reliability(cq, DDS_RELIABILITY_BEST_EFFORT, 0);
    dds_qset_history(cq, DDS_HISTORY_KEEP_ALL, 0);
    for (uint16_t i = 0; i < f->robot->n_groups; i++) {
        fgroup_t *g = &f->group[i];
        g->state_topic = dds_create_topic(f->participant, f->state_desc, g->g->state_topic,
                                          NULL, NULL);
        g->cmd_topic = dds_create_topic(f->participant, f->cmd_desc, g->g->command_topic, NULL,
                                        NULL);
        if (g->state_topic < 0 || g->cmd_topic < 0)
            return -1;
        g->state_writer = dds_create_writer(f->participant, g->state_topic, f->state_qos, NULL);
        dds_listener_t *l = dds_create_listener(g);
        dds_lset_data_available(l, on_command);
        g->cmd_reader = dds_create_reader(f->participant, g->cmd_topic, cq, l);
        dds_delete_listener(l);
        if (g->state_writer < 0 || g->cmd_reader < 0)
            return -1;
    }
    dds_delete_qos(cq);
    f->imu_topic = dds_create_topic(f->participant, f->imu_desc, f->robot->imu_topic, NULL, NULL);
    if (f->imu_topic < 0)
        return -1;
    f->imu_writer = dds_create_writer(f->participant, f->imu_topic, f->state_qos, NULL);
    return f->imu_writer < 0 ? -1 : 0;
}

/* The operator's writers, as rmw_cyclonedds makes a publisher with ROS 2's
 * default QoS (KEEP_LAST 10, RELIABLE, VOLATILE; teleop_twist_keyboard's
 * and joy's): types registered without type information. */
static int open_operator(fake_t *f)
{
    const dds_topic_descriptor_t *td, *jd;
    td = f->twist_desc = retype(&geometry_msgs_msg_dds__Twist__desc, NULL, 0);
    jd = f->joy_desc = retype(&sensor_msgs_msg_dds__Joy__desc, NULL, 0);
    if (td == NULL || jd == NULL)
        return -1;
    dds_qos_t *q = dds_create_qos();
    dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    dds_qset_history(q, DDS_HISTORY_KEEP_LAST, 10);
    dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
    dds_entity_t tt = dds_create_topic(f->participant, td, f->cmd_vel_topic, NULL, NULL);
    dds_entity_t jt = dds_create_topic(f->participant, jd, f->joy_topic, NULL, NULL);
    f->twist_writer = tt < 0 ? tt : dds_create_writer(f->participant, tt, q, NULL);
    f->joy_writer = jt < 0 ? jt : dds_create_writer(f->participant, jt, q, NULL);
    dds_delete_qos(q);
    return f->twist_writer < 0 || f->joy_writer < 0 ? -1 : 0;
}

static int write_twist(fake_t *f, const double *v)
{
    geometry_msgs_msg_dds__Twist_ t = { { v[0], v[1], v[2] }, { v[3], v[4], v[5] } };
    return dds_write(f->twist_writer, &t) == DDS_RETCODE_OK ? 0 : -1;
}

static int write_joy(fake_t *f)
{
    static char frame[] = "joy"; /* as ROS 2's joy node stamps its messages */
    sensor_msgs_msg_dds__Joy_ j;
    memset(&j, 0, sizeof j);
    pthread_mutex_lock(&f->pub_lock);
    f->clock_ns += CLOCK_STEP_NS;
    stamp_of(f->clock_ns, &j.header.stamp.sec, &j.header.stamp.nanosec);
    pthread_mutex_unlock(&f->pub_lock);
    j.header.frame_id = frame;
    j.axes._length = j.axes._maximum = f->joy_axes;
    j.axes._buffer = f->joy_axis;
    j.buttons._length = j.buttons._maximum = f->joy_buttons;
    j.buttons._buffer = f->joy_button;
    return dds_write(f->joy_writer, &j) == DDS_RETCODE_OK ? 0 : -1;
}

static uint32_t matched(dds_entity_t writer)
{
    dds_publication_matched_status_t st;
    if (dds_get_publication_matched_status(writer, &st) != DDS_RETCODE_OK)
        return 0;
    return st.current_count;
}

static uint32_t sub_matched(dds_entity_t reader)
{
    dds_subscription_matched_status_t st;
    if (dds_get_subscription_matched_status(reader, &st) != DDS_RETCODE_OK)
        return 0;
    return st.current_count;
}

/* A new writer for a state topic, once it meets the readers the old one
 * had (a rebooted robot's writers are new endpoints). pub_lock held. */
static dds_entity_t renew(fake_t *f, dds_entity_t topic, dds_entity_t old)
{
    uint32_t had = matched(old);
    (void)dds_delete(old);
    dds_entity_t w = dds_create_writer(f->participant, topic, f->state_qos, NULL);
    for (int i = 0; w > 0 && i < REMATCH_POLLS && matched(w) < had; i++)
        sleep_ms(1);
    return w;
}

/* ---- the periodic publisher ------------------------------------------------------- */

static void *period_main(void *arg)
{
    fake_t *f = arg;
    struct timespec next;
    clock_gettime(CLOCK_MONOTONIC, &next);
    for (;;) {
        pthread_mutex_lock(&f->lock);
        int stop = f->stopping;
        pthread_mutex_unlock(&f->lock);
        if (stop)
            return NULL;
        pthread_mutex_lock(&f->pub_lock);
        for (uint16_t g = 0; g <= f->robot->n_groups; g++) {
            int muted = g == f->robot->n_groups ? f->imu_muted : f->group[g].muted;
            if (!muted)
                (void)send_new(f, g);
        }
        pthread_mutex_unlock(&f->pub_lock);
        next.tv_nsec += (long)f->period_us * 1000L;
        while (next.tv_nsec >= 1000000000L) {
            next.tv_nsec -= 1000000000L;
            next.tv_sec++;
        }
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL) == EINTR)
            ;
    }
}

/* ---- requests ------------------------------------------------------------------------- */

/* The topic called @p name: a group's index, n_groups for "imu", -1. */
static int topic_index(const fake_t *f, const char *name)
{
    if (strcmp(name, "imu") == 0)
        return f->robot->n_groups;
    for (uint16_t g = 0; g < f->robot->n_groups; g++) {
        if (strcmp(f->group[g].g->name, name) == 0)
            return g;
    }
    return -1;
}

static int group_index(const fake_t *f, const char *name)
{
    int g = topic_index(f, name);
    return g >= 0 && g < f->robot->n_groups ? g : -1;
}

static int parse_u32(const char *s, uint32_t max, uint32_t *out)
{
    char *end;
    if (s == NULL || s[0] < '0' || s[0] > '9')
        return -1;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (errno != 0 || *end != '\0' || v > max)
        return -1;
    *out = (uint32_t)v;
    return 0;
}

static int parse_real(const char *s, double *out)
{
    char *end;
    if (s == NULL || s[0] == '\0')
        return -1;
    *out = strtod(s, &end);
    return *end == '\0' ? 0 : -1;
}

/* A group and a slot of it: argv[1], argv[2]. */
static int group_slot(const fake_t *f, char **argv, int *g, uint32_t *slot)
{
    *g = argv[1] != NULL ? group_index(f, argv[1]) : -1;
    return *g >= 0 && argv[2] != NULL && parse_u32(argv[2], FAKE_MAX_SLOTS - 1u, slot) == 0 ? 0
                                                                                              : -1;
}

/* The topics listed in argv[1..] (all state topics when none), as a mask. */
static int topic_mask(const fake_t *f, int argc, char **argv, uint32_t *mask)
{
    *mask = 0;
    if (argc == 1) {
        *mask = (1u << (f->robot->n_groups + 1u)) - 1u;
        return 0;
    }
    for (int i = 1; i < argc; i++) {
        int t = topic_index(f, argv[i]);
        if (t < 0)
            return -1;
        *mask |= 1u << t;
    }
    return 0;
}

static void print_command(const fcmd_t *c)
{
    printf("ok %u %u %u %s %u %u %u", c->sec, c->nanosec, c->seq, c->frame_id, c->ppt, c->n,
           c->min_len);
    for (uint32_t i = 0; i < c->n; i++)
        printf(" %s %.17g %.17g %.17g %.17g %.17g %.17g", c->name[i], c->q[i], c->dq[i],
               c->tau[i], c->kp[i], c->kd[i], c->extra[i]);
    putchar('\n');
    fflush(stdout);
}

static int do_restart(fake_t *f)
{
    pthread_mutex_lock(&f->pub_lock);
    for (uint16_t g = 0; g < f->robot->n_groups; g++) {
        fgroup_t *gr = &f->group[g];
        gr->state_writer = renew(f, gr->state_topic, gr->state_writer);
        gr->have_last = 0;
    }
    f->imu_writer = renew(f, f->imu_topic, f->imu_writer);
    f->imu_have_last = 0;
    f->clock_ns -= RESTART_BACK_NS;
    pthread_mutex_lock(&f->lock);
    for (uint16_t g = 0; g < f->robot->n_groups; g++) {
        f->group[g].model.seq = 0;
        f->group[g].have_cmd = 0;
    }
    pthread_mutex_unlock(&f->lock);
    pthread_mutex_unlock(&f->pub_lock);
    return 0;
}

/* One request; returns 1 on quit. */
static int handle(fake_t *f, int argc, char **argv)
{
    const char *r = argv[0];
    int g;
    uint32_t slot, u, mask;
    double v[10];

    if (strcmp(r, "joint") == 0 && argc == 6 && group_slot(f, argv, &g, &slot) == 0 &&
        parse_real(argv[3], &v[0]) == 0 && parse_real(argv[4], &v[1]) == 0 &&
        parse_real(argv[5], &v[2]) == 0) {
        pthread_mutex_lock(&f->lock);
        f->group[g].model.j[slot].q = v[0];
        f->group[g].model.j[slot].dq = v[1];
        f->group[g].model.j[slot].tau = v[2];
        pthread_mutex_unlock(&f->lock);
        return reply("ok");
    }
    if (strcmp(r, "joint_error") == 0 && argc == 4 && group_slot(f, argv, &g, &slot) == 0 &&
        parse_u32(argv[3], 65535u, &u) == 0) {
        pthread_mutex_lock(&f->lock);
        f->group[g].model.j[slot].error_code = (uint16_t)u;
        pthread_mutex_unlock(&f->lock);
        return reply("ok");
    }
    if (strcmp(r, "name") == 0 && argc == 4 && group_slot(f, argv, &g, &slot) == 0 &&
        strlen(argv[3]) <= NAME_MAX_LEN) {
        pthread_mutex_lock(&f->lock);
        snprintf(f->group[g].model.j[slot].name, NAME_MAX_LEN + 1, "%s",
                 strcmp(argv[3], "-") == 0 || strcmp(argv[3], "none") == 0 ? "" : argv[3]);
        f->group[g].model.j[slot].unnamed = strcmp(argv[3], "none") == 0;
        pthread_mutex_unlock(&f->lock);
        return reply("ok");
    }
    if (strcmp(r, "length") == 0 && argc == 3 && (g = group_index(f, argv[1])) >= 0 &&
        parse_u32(argv[2], FAKE_MAX_SLOTS, &u) == 0) {
        pthread_mutex_lock(&f->lock);
        f->group[g].model.length = u;
        pthread_mutex_unlock(&f->lock);
        return reply("ok");
    }
    if (strcmp(r, "error") == 0 && argc == 3 && (g = group_index(f, argv[1])) >= 0 &&
        parse_u32(argv[2], 255u, &u) == 0) {
        pthread_mutex_lock(&f->lock);
        f->group[g].model.error = (uint8_t)u;
        pthread_mutex_unlock(&f->lock);
        return reply("ok");
    }
    if (strcmp(r, "imu") == 0 && argc == 11) {
        for (int i = 0; i < 10; i++) {
            if (parse_real(argv[1 + i], &v[i]) != 0)
                return reply("err imu: bad value %s", argv[1 + i]);
        }
        pthread_mutex_lock(&f->lock);
        memcpy(f->imu, v, sizeof v);
        pthread_mutex_unlock(&f->lock);
        return reply("ok");
    }
    if ((strcmp(r, "send") == 0 || strcmp(r, "replay") == 0) &&
        topic_mask(f, argc, argv, &mask) == 0) {
        int replay = r[0] == 'r', bad = 0;
        pthread_mutex_lock(&f->pub_lock);
        for (uint16_t t = 0; t <= f->robot->n_groups; t++) {
            if (mask & (1u << t))
                bad |= (replay ? send_replay(f, t) : send_new(f, t)) != 0;
        }
        pthread_mutex_unlock(&f->pub_lock);
        return bad ? reply("err %s: nothing to %s, or a write failed", r, r) : reply("ok");
    }
    if ((strcmp(r, "mute") == 0 || strcmp(r, "unmute") == 0) && argc == 2 &&
        (g = topic_index(f, argv[1])) >= 0) {
        pthread_mutex_lock(&f->pub_lock);
        if (g == f->robot->n_groups)
            f->imu_muted = r[0] == 'm';
        else
            f->group[g].muted = r[0] == 'm';
        pthread_mutex_unlock(&f->pub_lock);
        return reply("ok");
    }
    if (strcmp(r, "stamp") == 0 && argc == 3 && argv[1][0] != '\0') {
        /* the next new sample of every topic carries exactly this stamp; a
         * valid one also sets the clock the later samples count from */
        char *end;
        long sec = strtol(argv[1], &end, 10);
        if (*end != '\0' || sec < INT32_MIN || sec > INT32_MAX ||
            parse_u32(argv[2], UINT32_MAX, &u) != 0)
            return reply("err stamp: expected SEC NSEC");
        pthread_mutex_lock(&f->pub_lock);
        f->raw_sec = (int32_t)sec;
        f->raw_nsec = u;
        f->raw_pending = (1 << (f->robot->n_groups + 1)) - 1;
        if (sec >= 0 && u <= 999999999u)
            f->clock_ns = (int64_t)sec * 1000000000LL + u - CLOCK_STEP_NS;
        pthread_mutex_unlock(&f->pub_lock);
        return reply("ok");
    }
    if (strcmp(r, "restart") == 0 && argc == 1) {
        do_restart(f);
        return reply("ok");
    }
    if (strcmp(r, "commands") == 0 && argc == 1) {
        line_t l = { "ok", 2 };
        pthread_mutex_lock(&f->lock);
        for (uint16_t i = 0; i < f->robot->n_groups; i++)
            line_add(&l, " %llu", (unsigned long long)f->group[i].commands);
        pthread_mutex_unlock(&f->lock);
        return reply("%s", l.s);
    }
    if (strcmp(r, "command") == 0 && argc == 2 && (g = group_index(f, argv[1])) >= 0) {
        fcmd_t c;
        pthread_mutex_lock(&f->lock);
        int have = f->group[g].have_cmd;
        c = f->group[g].cmd;
        pthread_mutex_unlock(&f->lock);
        if (!have)
            return reply("err none");
        print_command(&c);
        return 0;
    }
    if (strcmp(r, "wait_commands") == 0 && argc == 4 && (g = group_index(f, argv[1])) >= 0 &&
        parse_u32(argv[2], UINT32_MAX, &u) == 0 && parse_u32(argv[3], 600000u, &slot) == 0) {
        struct timespec dl;
        clock_gettime(CLOCK_REALTIME, &dl);
        dl.tv_sec += (time_t)(slot / 1000u);
        dl.tv_nsec += (long)(slot % 1000u) * 1000000L;
        if (dl.tv_nsec >= 1000000000L) {
            dl.tv_sec++;
            dl.tv_nsec -= 1000000000L;
        }
        pthread_mutex_lock(&f->lock);
        int rc = 0;
        while (f->group[g].commands < u && rc != ETIMEDOUT)
            rc = pthread_cond_timedwait(&f->changed, &f->lock, &dl);
        unsigned long long n = f->group[g].commands;
        pthread_mutex_unlock(&f->lock);
        return n >= u ? reply("ok %llu", n) : reply("err timeout %llu", n);
    }
    if (strcmp(r, "joints") == 0 && argc == 2 && (g = group_index(f, argv[1])) >= 0) {
        printf("ok %u", (unsigned)f->group[g].g->n_joints);
        for (uint16_t i = 0; i < f->group[g].g->n_joints; i++)
            printf(" %s", f->group[g].g->joints[i]);
        putchar('\n');
        fflush(stdout);
        return 0;
    }
    if (strcmp(r, "matched") == 0 && argc == 1) {
        /* discovery seen from this side: per group, the writers its command
         * reader matched and the readers its state writer matched; then the
         * IMU writer's readers */
        line_t l = { "ok", 2 };
        pthread_mutex_lock(&f->pub_lock);
        for (uint16_t i = 0; i < f->robot->n_groups; i++)
            line_add(&l, " %u %u", (unsigned)sub_matched(f->group[i].cmd_reader),
                     (unsigned)matched(f->group[i].state_writer));
        line_add(&l, " %u", (unsigned)matched(f->imu_writer));
        pthread_mutex_unlock(&f->pub_lock);
        return reply("%s", l.s);
    }
    /* the operator */
    if (strcmp(r, "twist") == 0 && argc == 7) {
        for (int i = 0; i < 6; i++) {
            if (parse_real(argv[1 + i], &v[i]) != 0)
                return reply("err twist: expected six reals");
        }
        return write_twist(f, v) == 0 ? reply("ok") : reply("err twist: dds_write failed");
    }
    if (strcmp(r, "joy_length") == 0 && argc == 3 && parse_u32(argv[1], JOY_MAX, &u) == 0 &&
        parse_u32(argv[2], JOY_MAX, &slot) == 0) {
        f->joy_axes = u;
        f->joy_buttons = slot;
        return reply("ok");
    }
    if (strcmp(r, "joy_axis") == 0 && argc == 3 &&
        parse_u32(argv[1], JOY_MAX - 1u, &u) == 0 && parse_real(argv[2], &v[0]) == 0) {
        f->joy_axis[u] = (float)v[0];
        return reply("ok");
    }
    if (strcmp(r, "joy_button") == 0 && argc == 3 &&
        parse_u32(argv[1], JOY_MAX - 1u, &u) == 0 && parse_u32(argv[2], 1u, &slot) == 0) {
        f->joy_button[u] = (int32_t)slot;
        return reply("ok");
    }
    if (strcmp(r, "joy") == 0 && argc == 1)
        return write_joy(f) == 0 ? reply("ok") : reply("err joy: dds_write failed");
    if (strcmp(r, "operator_matched") == 0 && argc == 1)
        return reply("ok %u %u", (unsigned)matched(f->twist_writer),
                     (unsigned)matched(f->joy_writer));
    if (strcmp(r, "groups") == 0 && argc == 1) {
        printf("ok %u", (unsigned)f->robot->n_groups);
        for (uint16_t i = 0; i < f->robot->n_groups; i++)
            printf(" %s", f->group[i].g->name);
        putchar('\n');
        fflush(stdout);
        return 0;
    }
    if (strcmp(r, "quit") == 0 && argc == 1) {
        reply("ok");
        return 1;
    }
    return reply("err %s: unknown request or bad arguments", r);
}

/* ---- main ---------------------------------------------------------------------------- */

static int usage(const char *why)
{
    fprintf(stderr,
            "fake_ros2: %s\nusage: fake_ros2 --robot pm01|x2 --domain N [--period-us P] "
            "[--typeinfo on|off] [--joint-state-layout sdk|docs] [--cmd-vel-topic T] "
            "[--joy-topic T]\n",
            why);
    return 2;
}

int main(int argc, char **argv)
{
    fake_t *f = &fake;
    uint32_t domain = UINT32_MAX;
    char line[LINE_MAX_LEN + 2];

    f->typeinfo = 1;
    f->cmd_vel_topic = "rt/cmd_vel";
    f->joy_topic = "rt/joy";
    for (int i = 1; i < argc; i += 2) { /* options come as pairs: --name value */
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(argv[i], "--robot") == 0 && v != NULL) {
            f->robot = fake_robot_find(v);
            if (f->robot == NULL)
                return usage("--robot: expected pm01 or x2");
        } else if (strcmp(argv[i], "--domain") == 0 && v != NULL) {
            if (parse_u32(v, 232u, &domain) != 0)
                return usage("--domain: expected 0..232");
        } else if (strcmp(argv[i], "--period-us") == 0 && v != NULL) {
            if (parse_u32(v, MAX_PERIOD_US, &f->period_us) != 0 ||
                (f->period_us != 0 && f->period_us < MIN_PERIOD_US))
                return usage("--period-us: expected 0 or 100..1000000");
        } else if (strcmp(argv[i], "--typeinfo") == 0 && v != NULL &&
                   (strcmp(v, "on") == 0 || strcmp(v, "off") == 0)) {
            f->typeinfo = strcmp(v, "on") == 0;
        } else if (strcmp(argv[i], "--joint-state-layout") == 0 && v != NULL &&
                   (strcmp(v, "sdk") == 0 || strcmp(v, "docs") == 0)) {
            f->docs_layout = strcmp(v, "docs") == 0;
        } else if (strcmp(argv[i], "--cmd-vel-topic") == 0 && v != NULL) {
            f->cmd_vel_topic = v;
        } else if (strcmp(argv[i], "--joy-topic") == 0 && v != NULL) {
            f->joy_topic = v;
        } else {
            return usage("unknown option or missing value");
        }
    }
    if (f->robot == NULL || domain == UINT32_MAX)
        return usage("--robot and --domain are required");
    pthread_mutex_init(&f->lock, NULL);
    pthread_mutex_init(&f->pub_lock, NULL);
    pthread_cond_init(&f->changed, NULL);
    f->clock_ns = CLOCK_START_NS;
    f->imu[3] = 1.0; /* upright */
    for (uint16_t g = 0; g < f->robot->n_groups; g++) {
        f->group[g].g = &f->robot->groups[g];
        f->group[g].model.length = f->robot->groups[g].n_joints;
    }
    f->joy_axes = 6; /* ROS 2 joy's game_controller_node: 6 axes, 21 buttons */
    f->joy_buttons = 21;
    if (open_dds(f, domain) != 0 || open_operator(f) != 0) {
        fprintf(stderr, "fake_ros2: DDS on domain %u failed\n", domain);
        return 1;
    }
    if (f->period_us != 0) {
        if (pthread_create(&f->period_thread, NULL, period_main, f) != 0)
            return 1;
        f->period_running = 1;
    }
    reply("ready");
    while (fgets(line, sizeof line, stdin) != NULL) {
        char *args[16];
        int n = 0;
        if (strchr(line, '\n') == NULL && !feof(stdin)) {
            int c;
            while ((c = getchar()) != EOF && c != '\n')
                ;
            reply("err line too long");
            continue;
        }
        for (char *tok = strtok(line, " \t\r\n"); tok != NULL && n < 15;
             tok = strtok(NULL, " \t\r\n"))
            args[n++] = tok;
        args[n] = NULL;
        if (n == 0) {
            reply("err empty");
            continue;
        }
        int rc = handle(f, n, args);
        if (rc != 0)
            break;
    }
    pthread_mutex_lock(&f->lock);
    f->stopping = 1;
    pthread_mutex_unlock(&f->lock);
    if (f->period_running)
        pthread_join(f->period_thread, NULL);
    (void)dds_delete(f->participant);
    dds_delete_qos(f->state_qos);
    return 0;
}
