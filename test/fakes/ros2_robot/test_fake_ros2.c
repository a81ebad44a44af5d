/* SPDX-License-Identifier: Apache-2.0 */
/* The fake ROS 2 robot's own test, apart from the ports: it runs fake_ros2
 * as the ports' tests do and watches the wire with Cyclone DDS readers and
 * writers of its own. What the fake publishes is taken as the bytes that
 * travelled (dds_takecdr) and checked against XCDR1 offsets worked out by
 * hand below from the .msg definitions (std_msgs/Header, sensor_msgs/Imu,
 * interface_protocol/JointState and ImuInfo, aimdk_msgs/JointStateArray in
 * both JointState layouts); what it receives is written as bytes assembled
 * here by hand (dds_writecdr) and must come back from the fake's "command"
 * request as written. Joint names and orders are this file's own copy of
 * the vendors' tables. So neither the fake's IDL nor its robot tables nor
 * any port code stands between a mistake and this test.
 *
 * XCDR1 as rmw_cyclonedds writes it: a 4-byte encapsulation header (0x00
 * 0x01 = little-endian CDR, then 2 option bytes); offsets count from after
 * it; every primitive aligned to its size (8 for float64); a string is a
 * uint32 length counting its NUL, its bytes, the NUL; a sequence a uint32
 * count, then its elements; a float64[9] nine float64 in line. */
#define _GNU_SOURCE
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <dds/dds.h>
#include <dds/ddsi/ddsi_serdata.h>

#include "fake_dds.h"
#include "fake_ros2_client.h"
#include "ros2_robot.h"

#ifndef ROZ_TEST_DDS_DOMAIN
#error "ROZ_TEST_DDS_DOMAIN: a domain id of this test's own"
#endif

#define WIRE_MS 10000 /* a sample later than this is lost */

/* ---- the vendors' joint tables, this file's own copy ---------------------------- */

static const char *const x2_arm[14] = {
    "left_shoulder_pitch_joint",  "left_shoulder_roll_joint",  "left_shoulder_yaw_joint",
    "left_elbow_joint",           "left_wrist_yaw_joint",      "left_wrist_pitch_joint",
    "left_wrist_roll_joint",      "right_shoulder_pitch_joint", "right_shoulder_roll_joint",
    "right_shoulder_yaw_joint",   "right_elbow_joint",         "right_wrist_yaw_joint",
    "right_wrist_pitch_joint",    "right_wrist_roll_joint",
};
static const char *const x2_head[2] = { "head_yaw_joint", "head_pitch_joint" };

/* ---- reading XCDR1 by hand ------------------------------------------------------------ */

typedef struct {
    const uint8_t *b; /* the payload, after the encapsulation header */
    size_t         n, at;
} cdr_t;

static void cdr_align(cdr_t *c, size_t k)
{
    c->at = (c->at + k - 1) / k * k;
}

static uint64_t le(const cdr_t *c, size_t at, size_t size)
{
    if (at + size > c->n)
        fail_msg("reading %zu bytes at offset %zu of a %zu-byte payload", size, at, c->n);
    uint64_t v = 0;
    for (size_t i = 0; i < size; i++)
        v |= (uint64_t)c->b[at + i] << (8 * i);
    return v;
}

static uint64_t cdr_uint(cdr_t *c, size_t size)
{
    cdr_align(c, size);
    uint64_t v = le(c, c->at, size);
    c->at += size;
    return v;
}

static double cdr_f64(cdr_t *c)
{
    uint64_t bits = cdr_uint(c, 8);
    double d;
    memcpy(&d, &bits, sizeof d);
    return d;
}

/* A string: its length (with the NUL) must be strlen + 1, its last byte 0. */
static void cdr_string(cdr_t *c, char *out, size_t len)
{
    uint32_t n = (uint32_t)cdr_uint(c, 4);
    if (n == 0 || c->at + n > c->n || c->b[c->at + n - 1] != 0 || n > len)
        fail_msg("a string of length %u at offset %zu is not a string", n, c->at - 4);
    memcpy(out, c->b + c->at, n);
    if (strlen(out) + 1 != n)
        fail_msg("a string of length %u holds \"%s\"", n, out);
    c->at += n;
}

/* The value at a fixed offset, and where the cursor stands: both hand-worked. */
static void expect_at(const cdr_t *c, size_t want)
{
    if (c->at != want)
        fail_msg("the cursor is at offset %zu, the hand-worked layout says %zu", c->at, want);
}

static void expect_f64_at(const cdr_t *c, size_t at, double want)
{
    uint64_t bits = le(c, at, 8), wbits;
    memcpy(&wbits, &want, sizeof wbits);
    if (bits != wbits)
        fail_msg("float64 at offset %zu: 0x%016llx, want %.17g", at, (unsigned long long)bits,
                 want);
}

/* ---- writing XCDR1 by hand ------------------------------------------------------------ */

typedef struct {
    uint8_t b[8192]; /* header + payload */
    size_t  at;      /* payload bytes */
} out_t;

static void out_init(out_t *o)
{
    memset(o, 0, sizeof *o);
    o->b[0] = 0x00;
    o->b[1] = 0x01; /* CDR, little-endian */
}

static void out_uint(out_t *o, uint64_t v, size_t size)
{
    o->at = (o->at + size - 1) / size * size;
    assert_true(4 + o->at + size <= sizeof o->b);
    for (size_t i = 0; i < size; i++)
        o->b[4 + o->at + i] = (uint8_t)(v >> (8 * i));
    o->at += size;
}

static void out_f64(out_t *o, double d)
{
    uint64_t bits;
    memcpy(&bits, &d, sizeof bits);
    out_uint(o, bits, 8);
}

static void out_string(out_t *o, const char *s)
{
    size_t n = strlen(s) + 1;
    out_uint(o, n, 4);
    assert_true(4 + o->at + n <= sizeof o->b);
    memcpy(o->b + 4 + o->at, s, n);
    o->at += n;
}

/* ---- the fake and this test's own participant ------------------------------------------ */

static roz_fake_ros2_t fake;
static dds_entity_t part;

static void start(const char *robot, const char *const *extra)
{
    char err[256] = "";
    if (roz_fake_ros2_start(&fake, robot, ROZ_TEST_DDS_DOMAIN, extra, err, sizeof err) != 0)
        fail_msg("%s", err);
}

static int teardown(void **st)
{
    (void)st;
    assert_int_equal(roz_fake_ros2_stop(&fake), 0);
    return 0;
}

static void ask(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static void ask(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    roz_fake_process_vmust(&fake.proc, "fake_ros2", fmt, ap);
    va_end(ap);
}

static int setup_dds(void **st)
{
    (void)st;
    part = fake_dds_participant(ROZ_TEST_DDS_DOMAIN, "test_fake_ros2");
    return part < 0 ? -1 : 0;
}

static int teardown_dds(void **st)
{
    (void)st;
    dds_delete(part);
    return 0;
}

/* A reader on @p topic (type @p desc: only its name and type information
 * count, the bytes are read here), matched with the fake's writer. */
static dds_entity_t wire_reader(const dds_topic_descriptor_t *desc, const char *topic)
{
    dds_entity_t t = dds_create_topic(part, desc, topic, NULL, NULL);
    assert_true(t > 0);
    dds_qos_t *q = dds_create_qos();
    dds_qset_reliability(q, DDS_RELIABILITY_BEST_EFFORT, 0);
    dds_qset_history(q, DDS_HISTORY_KEEP_ALL, 0);
    dds_entity_t r = dds_create_reader(part, t, q, NULL);
    dds_delete_qos(q);
    assert_true(r > 0);
    dds_subscription_matched_status_t ms;
    for (int i = 0; i < WIRE_MS; i++) {
        assert_true(dds_get_subscription_matched_status(r, &ms) >= 0);
        if (ms.current_count >= 1)
            return r;
        dds_sleepfor(DDS_MSECS(1));
    }
    fail_msg("%s: the fake's writer was not discovered", topic);
    return 0;
}

/* Asks the fake @p request (every 500 ms) until a sample arrives at @p r (a
 * sample sent before both sides discovered each other is lost), then
 * returns its bytes: the encapsulation header, then the payload. */
static size_t take_asked(dds_entity_t r, const char *request, uint8_t *buf, size_t cap)
{
    struct ddsi_serdata *sd = NULL;
    dds_sample_info_t info;
    for (int ms = 0; ms < WIRE_MS; ms++) {
        if (ms % 500 == 0)
            ask("%s", request);
        if (dds_takecdr(r, &sd, 1, &info, DDS_ANY_STATE) == 1) {
            size_t n = ddsi_serdata_size(sd);
            if (n > cap)
                fail_msg("a serialized sample of %zu bytes", n);
            ddsi_serdata_to_ser(sd, 0, n, buf);
            ddsi_serdata_unref(sd);
            /* XCDR1, little-endian: what rmw_cyclonedds reads */
            assert_int_equal(buf[0], 0x00);
            assert_int_equal(buf[1], 0x01);
            return n;
        }
        dds_sleepfor(DDS_MSECS(1));
    }
    fail_msg("no sample after \"%s\"", request);
    return 0;
}

/* New samples on @p what ("send WHAT") until one arrives: take_asked(). */
static size_t take_wire(dds_entity_t r, const char *what, uint8_t *buf, size_t cap)
{
    char request[128];
    snprintf(request, sizeof request, "send %s", what);
    return take_asked(r, request, buf, cap);
}

/* Takes whatever else arrived (the resends), so the next take is new. */
static void drain(dds_entity_t r)
{
    struct ddsi_serdata *sd = NULL;
    dds_sample_info_t info;
    dds_sleepfor(DDS_MSECS(20));
    while (dds_takecdr(r, &sd, 1, &info, DDS_ANY_STATE) == 1)
        ddsi_serdata_unref(sd);
}

/* A header as std_msgs/Header: stamp (int32 sec @0, uint32 nanosec @4),
 * frame_id (the fake's is empty: length 1 @8, its NUL @12); next: 13. */
static void expect_header(cdr_t *c, int32_t sec, uint32_t nanosec)
{
    char id[64];
    assert_int_equal((int32_t)le(c, 0, 4), sec);
    assert_int_equal((uint32_t)le(c, 4, 4), nanosec);
    assert_int_equal(le(c, 8, 4), 1);
    assert_int_equal(c->b[12], 0);
    c->at = 8;
    cdr_string(c, id, sizeof id);
    expect_at(c, 13);
}

/* @p what's sample once the fake stamps the next at @p sec, @p nanosec,
 * after discovery (a first sample taken, the resends drained): its bytes in
 * @p buf; their number. */
static size_t take_stamped(dds_entity_t r, const char *what, uint8_t *buf, size_t cap,
                           int32_t sec, uint32_t nanosec)
{
    (void)take_wire(r, what, buf, cap); /* discovery */
    drain(r);
    ask("stamp %ld %lu", (long)sec, (unsigned long)nanosec);
    return take_wire(r, what, buf, cap);
}

/* The payload of the @p n bytes at @p buf, which must be @p size bytes
 * after a header stamped @p sec, @p nanosec. */
static cdr_t stamped_payload(const uint8_t *buf, size_t n, size_t size, int32_t sec,
                             uint32_t nanosec)
{
    cdr_t c = { buf + 4, n - 4, 0 };
    assert_int_equal(c.n, size);
    expect_header(&c, sec, nanosec);
    return c;
}

/* ---- what the fake sends ------------------------------------------------------------------ */

static double q_of(unsigned i)
{
    return 0.25 + i;
}
static double dq_of(unsigned i)
{
    return -0.5 - 2.0 * i;
}
static double tau_of(unsigned i)
{
    return 0.125 * i + 100.0;
}

/* interface_protocol/JointState: Header header; float64[] position,
 * velocity, torque. With an empty frame_id and 24 joints: header 0..12;
 * position count @16, values @24 + 8i (to 216); velocity count @216,
 * values @224 + 8i; torque count @416, values @424 + 8i; 616 bytes. */
static void test_pm01_joint_state_bytes(void **st)
{
    uint8_t buf[4096];
    (void)st;
    start("pm01", NULL);
    dds_entity_t r = wire_reader(&interface_protocol_msg_dds__JointState__desc,
                                 "rt/hardware/joint_state");
    for (unsigned i = 0; i < 24; i++)
        ask("joint body %u %.17g %.17g %.17g", i, q_of(i), dq_of(i), tau_of(i));
    size_t n = take_stamped(r, "body", buf, sizeof buf, 1700000123, 456789);
    cdr_t c = stamped_payload(buf, n, 616, 1700000123, 456789);
    assert_int_equal(le(&c, 16, 4), 24);
    assert_int_equal(le(&c, 216, 4), 24);
    assert_int_equal(le(&c, 416, 4), 24);
    for (unsigned i = 0; i < 24; i++) {
        expect_f64_at(&c, 24 + 8 * i, q_of(i));
        expect_f64_at(&c, 224 + 8 * i, dq_of(i));
        expect_f64_at(&c, 424 + 8 * i, tau_of(i));
    }
    dds_delete(r);
}

/* interface_protocol/ImuInfo: Header header; geometry_msgs/Quaternion
 * quaternion (x, y, z, w); Vector3 rpy, linear_acceleration,
 * angular_velocity. Header 0..12, then float64s from 16: quaternion
 * @16, 24, 32, 40; rpy @48, 56, 64; linear_acceleration @72, 80, 88;
 * angular_velocity @96, 104, 112; 120 bytes. The fake's "imu" request
 * takes orientation, angular velocity, linear acceleration. */
static void test_pm01_imu_bytes(void **st)
{
    uint8_t buf[1024];
    (void)st;
    start("pm01", NULL);
    dds_entity_t r = wire_reader(&interface_protocol_msg_dds__ImuInfo__desc,
                                 "rt/hardware/imu_info");
    ask("imu 0.5 -0.25 0.125 0.75 1.5 2.5 3.5 -9.5 0.0625 9.75");
    size_t n = take_stamped(r, "imu", buf, sizeof buf, 1700000200, 999999999u);
    cdr_t c = stamped_payload(buf, n, 120, 1700000200, 999999999u);
    static const double q[4] = { 0.5, -0.25, 0.125, 0.75 };
    for (unsigned k = 0; k < 4; k++)
        expect_f64_at(&c, 16 + 8 * k, q[k]);
    for (unsigned k = 0; k < 3; k++)
        expect_f64_at(&c, 48 + 8 * k, 0.0); /* rpy: the fake sends none */
    expect_f64_at(&c, 72, -9.5);
    expect_f64_at(&c, 80, 0.0625);
    expect_f64_at(&c, 88, 9.75);
    expect_f64_at(&c, 96, 1.5);
    expect_f64_at(&c, 104, 2.5);
    expect_f64_at(&c, 112, 3.5);
    dds_delete(r);
}

/* aimdk_msgs/JointStateArray: MessageHeader header (Time stamp @0, @4;
 * string frame_id: length @8, NUL @12; uint32 sequence @16; Time
 * meas_stamp @20, @24); DomainErrorState state (uint8 value @28); then
 * JointState[] joints: count @32, then per joint: string name (length
 * aligned to 4), float64 position, velocity, effort (aligned to 8), and
 * the layout's tail: the SDK's uint16 error_code, or the documentation's
 * uint8 coil_temp, motor_temp, motor_vol. The arm's first joint,
 * "left_shoulder_pitch_joint" (25 characters): length @36 = 26, bytes
 * @40..65, position @72, velocity @80, effort @88, error_code @96 (the
 * docs' three uint8 @96, 97, 98); the next name's length @100. */
static void check_x2_arm(const uint8_t *buf, size_t n, int docs, uint32_t *seq)
{
    cdr_t c = { buf + 4, n - 4, 0 };
    char name[64];
    expect_header(&c, 1700000300, 5000);
    c.at = 16;
    *seq = (uint32_t)cdr_uint(&c, 4);
    assert_int_equal(cdr_uint(&c, 4), 1700000300); /* meas_stamp = stamp */
    assert_int_equal(cdr_uint(&c, 4), 5000);
    expect_at(&c, 28);
    assert_int_equal(cdr_uint(&c, 1), 3); /* DomainErrorState: disabled */
    assert_int_equal(cdr_uint(&c, 4), 14);
    expect_at(&c, 36);
    for (unsigned i = 0; i < 14; i++) {
        if (i == 0)
            assert_int_equal(le(&c, 36, 4), 26);
        if (i == 1)
            assert_int_equal(le(&c, 100, 4), strlen(x2_arm[1]) + 1);
        cdr_string(&c, name, sizeof name);
        assert_string_equal(name, x2_arm[i]);
        if (i == 0)
            expect_at(&c, 66);
        assert_true(cdr_f64(&c) == q_of(i));
        if (i == 0)
            expect_at(&c, 80);
        assert_true(cdr_f64(&c) == dq_of(i));
        assert_true(cdr_f64(&c) == tau_of(i));
        if (i == 0)
            expect_at(&c, 96);
        if (docs) {
            assert_int_equal(cdr_uint(&c, 1), 41); /* the fake's coil_temp */
            assert_int_equal(cdr_uint(&c, 1), 38); /* motor_temp */
            assert_int_equal(cdr_uint(&c, 1), 48); /* motor_vol */
        } else {
            assert_int_equal(cdr_uint(&c, 2), i == 5 ? 517 : 0);
        }
    }
    /* nothing after the last joint but the padding to 4 bytes */
    assert_true(c.n - c.at < 4);
    for (size_t k = c.at; k < c.n; k++)
        assert_int_equal(c.b[k], 0);
}

/* The documentation's layout as the fake sends it: under the SDK's type
 * name, without type information. */
static const dds_topic_descriptor_t *docs_desc(void)
{
    static dds_topic_descriptor_t *d;
    const dds_topic_descriptor_t *src = &fake_x2_docs_msg_dds__JointStateArray__desc;
    const struct dds_type_meta_ser none = { NULL, 0 };
    const dds_topic_descriptor_t renamed = {
        .m_size = src->m_size,
        .m_align = src->m_align,
        .m_flagset = src->m_flagset & ~DDS_TOPIC_XTYPES_METADATA,
        .m_nkeys = src->m_nkeys,
        .m_typename = "aimdk_msgs::msg::dds_::JointStateArray_",
        .m_keys = src->m_keys,
        .m_nops = src->m_nops,
        .m_ops = src->m_ops,
        .m_meta = src->m_meta,
        .type_information = none,
        .type_mapping = none,
        .restrict_data_representation = src->restrict_data_representation,
    };
    if (d == NULL)
        d = malloc(sizeof *d);
    assert_non_null(d);
    memcpy(d, &renamed, sizeof renamed);
    return d;
}

static void x2_arm_case(int docs)
{
    static const char *const docs_args[] = { "--joint-state-layout", "docs", NULL };
    uint8_t buf[4096];
    uint32_t seq0, seq1;
    start("x2", docs ? docs_args : NULL);
    dds_entity_t r = wire_reader(docs ? docs_desc() : &aimdk_msgs_msg_dds__JointStateArray__desc,
                                 "rt/aima/hal/joint/arm/state");
    for (unsigned i = 0; i < 14; i++)
        ask("joint arm %u %.17g %.17g %.17g", i, q_of(i), dq_of(i), tau_of(i));
    ask("error arm 3");
    if (!docs)
        ask("joint_error arm 5 517");
    size_t n = take_stamped(r, "arm", buf, sizeof buf, 1700000300, 5000);
    check_x2_arm(buf, n, docs, &seq0);
    ask("stamp 1700000300 5000");
    n = take_wire(r, "arm", buf, sizeof buf);
    check_x2_arm(buf, n, docs, &seq1);
    assert_int_equal(seq1, seq0 + 1); /* the header's sequence counts the group's samples */
    dds_delete(r);
}

static void test_x2_joint_state_bytes(void **st)
{
    (void)st;
    x2_arm_case(0);
}

static void test_x2_docs_joint_state_bytes(void **st)
{
    (void)st;
    x2_arm_case(1);
}

/* sensor_msgs/Imu: Header header; Quaternion orientation @16, 24, 32, 40;
 * float64[9] orientation_covariance @48 + 8k; Vector3 angular_velocity
 * @120, 128, 136; float64[9] @144 + 8k; Vector3 linear_acceleration @216,
 * 224, 232; float64[9] @240 + 8k; 312 bytes. */
static void test_x2_imu_bytes(void **st)
{
    uint8_t buf[1024];
    (void)st;
    start("x2", NULL);
    dds_entity_t r = wire_reader(&sensor_msgs_msg_dds__Imu__desc, "rt/aima/hal/imu/torso/state");
    ask("imu 0.5 -0.25 0.125 0.75 1.5 2.5 3.5 -9.5 0.0625 9.75");
    size_t n = take_stamped(r, "imu", buf, sizeof buf, 1700000400, 1);
    cdr_t c = stamped_payload(buf, n, 312, 1700000400, 1);
    static const double q[4] = { 0.5, -0.25, 0.125, 0.75 };
    for (unsigned k = 0; k < 4; k++)
        expect_f64_at(&c, 16 + 8 * k, q[k]);
    expect_f64_at(&c, 120, 1.5);
    expect_f64_at(&c, 128, 2.5);
    expect_f64_at(&c, 136, 3.5);
    expect_f64_at(&c, 216, -9.5);
    expect_f64_at(&c, 224, 0.0625);
    expect_f64_at(&c, 232, 9.75);
    for (unsigned k = 0; k < 9; k++) {
        expect_f64_at(&c, 48 + 8 * k, 0.0);
        expect_f64_at(&c, 144 + 8 * k, 0.0);
        expect_f64_at(&c, 240 + 8 * k, 0.0);
    }
    dds_delete(r);
}

/* ---- what the fake receives ------------------------------------------------------------- */

/* A writer on @p topic, and its sertype (taken from a sample this test
 * writes to itself), for bytes assembled here. */
typedef struct {
    dds_entity_t               writer;
    const struct ddsi_sertype *type;
    struct ddsi_serdata       *probe; /* holds the type */
} raw_writer_t;

/* Waits until the fake's command reader of group @p g matched a writer:
 * until then, what is written goes nowhere. */
static void await_fake_reader(unsigned g)
{
    for (int ms = 0; ms < WIRE_MS; ms += 5) {
        ask("matched");
        char *p = fake.proc.line + 2, *end;
        unsigned long v = 0;
        for (unsigned k = 0; k <= 2 * g; k++) {
            v = strtoul(p, &end, 10);
            assert_true(end != p);
            p = end;
        }
        if (v >= 1)
            return;
        dds_sleepfor(DDS_MSECS(5));
    }
    fail_msg("the fake's command reader of group %u matched no writer", g);
}

static void raw_writer(raw_writer_t *w, const dds_topic_descriptor_t *desc, const char *topic,
                       unsigned group, const void *zero_sample)
{
    dds_entity_t t = dds_create_topic(part, desc, topic, NULL, NULL);
    assert_true(t > 0);
    dds_qos_t *q = dds_create_qos();
    dds_qset_reliability(q, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    dds_qset_history(q, DDS_HISTORY_KEEP_ALL, 0);
    w->writer = dds_create_writer(part, t, q, NULL);
    dds_entity_t self = dds_create_reader(part, t, q, NULL);
    dds_delete_qos(q);
    assert_true(w->writer > 0 && self > 0);
    dds_publication_matched_status_t ms;
    for (int i = 0; i < WIRE_MS; i++) {
        assert_true(dds_get_publication_matched_status(w->writer, &ms) >= 0);
        if (ms.current_count >= 2) /* this test's own reader and the fake's */
            break;
        dds_sleepfor(DDS_MSECS(1));
    }
    if (ms.current_count < 2)
        fail_msg("%s: the fake's reader was not discovered", topic);
    await_fake_reader(group);
    dds_sample_info_t info;
    assert_int_equal(dds_write(w->writer, zero_sample), 0);
    w->probe = NULL;
    for (int i = 0; i < WIRE_MS && w->probe == NULL; i++) {
        if (dds_takecdr(self, &w->probe, 1, &info, DDS_ANY_STATE) != 1) {
            w->probe = NULL;
            dds_sleepfor(DDS_MSECS(1));
        }
    }
    assert_non_null(w->probe);
    w->type = w->probe->type;
    dds_delete(self);
}

static void raw_write(raw_writer_t *w, const out_t *o)
{
    ddsrt_iovec_t iov = { (void *)(uintptr_t)o->b, (ddsrt_iov_len_t)(4 + o->at) };
    struct ddsi_serdata *sd = ddsi_serdata_from_ser_iov(w->type, SDK_DATA, 1, &iov, 4 + o->at);
    assert_non_null(sd);
    assert_int_equal(dds_writecdr(w->writer, sd), 0);
}

static void raw_close(raw_writer_t *w)
{
    ddsi_serdata_unref(w->probe);
    dds_delete(w->writer);
}

/* Waits until the fake counted @p n commands on group @p g. */
static void await_commands(unsigned g, uint64_t n)
{
    uint64_t counts[FAKE_ROS2_MAX_GROUPS];
    for (int ms = 0; ms < WIRE_MS; ms += 5) {
        assert_int_equal(roz_fake_ros2_commands(&fake, counts), 0);
        if (counts[g] >= n)
            return;
        dds_sleepfor(DDS_MSECS(5));
    }
    (void)roz_fake_ros2_ask(&fake, "matched");
    fail_msg("the fake counted %llu commands on group %u, expected %llu (matched: %s)",
             (unsigned long long)counts[g], g, (unsigned long long)n, fake.proc.line);
}

/* interface_protocol/JointCommand: Header header; float64[] position,
 * velocity, feed_forward_torque, torque, stiffness, damping; uint8
 * parallel_parser_type. Written here field by field; the fake must report
 * each array in its place, and parallel_parser_type. */
static void test_pm01_command_as_written(void **st)
{
    static out_t o;
    raw_writer_t w;
    roz_fake_ros2_cmd_t c;
    interface_protocol_msg_dds__JointCommand_ zero;
    (void)st;
    start("pm01", NULL);
    memset(&zero, 0, sizeof zero);
    zero.header.frame_id = (char *)(uintptr_t)"";
    raw_writer(&w, &interface_protocol_msg_dds__JointCommand__desc, "rt/hardware/joint_command",
               0, &zero);
    await_commands(0, 1); /* this test's own probe */

    out_init(&o);
    out_uint(&o, 1700000500, 4);
    out_uint(&o, 250, 4);
    out_string(&o, "base");
    for (unsigned a = 0; a < 6; a++) {
        out_uint(&o, 24, 4);
        for (unsigned i = 0; i < 24; i++)
            out_f64(&o, 1000.0 * a + i + 0.5);
    }
    out_uint(&o, 1, 1);
    /* by hand: frame_id's length @8, "base\0" @12..16; position's count
     * @20, values @24 + 8i; each next array 200 further (its count 4-aligned,
     * values 8-aligned): damping's count @1016, values @1024 + 8i; ppt @1216 */
    assert_int_equal(o.at, 1217);
    raw_write(&w, &o);
    await_commands(0, 2);
    assert_int_equal(roz_fake_ros2_command(&fake, 0, &c), 1);
    assert_int_equal(c.sec, 1700000500);
    assert_int_equal(c.nanosec, 250);
    assert_string_equal(c.frame_id, "base");
    assert_int_equal(c.ppt, 1);
    assert_int_equal(c.n, 24);
    assert_int_equal(c.min_len, 24);
    for (unsigned i = 0; i < 24; i++) {
        assert_true(c.q[i] == 0.0 + i + 0.5);
        assert_true(c.dq[i] == 1000.0 + i + 0.5);
        assert_true(c.tau[i] == 2000.0 + i + 0.5);   /* feed_forward_torque */
        assert_true(c.extra[i] == 3000.0 + i + 0.5); /* torque */
        assert_true(c.kp[i] == 4000.0 + i + 0.5);
        assert_true(c.kd[i] == 5000.0 + i + 0.5);
    }
    raw_close(&w);
}

/* aimdk_msgs/JointCommandArray: MessageHeader header; JointCommand[]
 * joints, each string name; float64 position, velocity, effort,
 * stiffness, damping. */
static void test_x2_command_as_written(void **st)
{
    static out_t o;
    raw_writer_t w;
    roz_fake_ros2_cmd_t c;
    aimdk_msgs_msg_dds__JointCommandArray_ zero;
    (void)st;
    start("x2", NULL);
    int head = roz_fake_ros2_group(&fake, "head");
    assert_true(head >= 0);
    memset(&zero, 0, sizeof zero);
    zero.header.frame_id = (char *)(uintptr_t)"";
    raw_writer(&w, &aimdk_msgs_msg_dds__JointCommandArray__desc,
               "rt/aima/hal/joint/head/command", (unsigned)head, &zero);
    await_commands((unsigned)head, 1);

    out_init(&o);
    out_uint(&o, 1700000600, 4);
    out_uint(&o, 42, 4);
    out_string(&o, "f");          /* length @8, "f\0" @12..13 */
    out_uint(&o, 77, 4);          /* sequence @16 */
    out_uint(&o, 1700000601, 4);  /* meas_stamp @20, @24 */
    out_uint(&o, 43, 4);
    out_uint(&o, 2, 4);           /* joints @28 */
    for (unsigned i = 0; i < 2; i++) {
        out_string(&o, x2_head[i]); /* the first @32: 15, "head_yaw_joint\0" @36..50 */
        for (unsigned k = 0; k < 5; k++)
            out_f64(&o, 10.0 * k + i + 0.25); /* the first's position @56 */
    }
    /* the second name's length @96, "head_pitch_joint\0" @100..116, its
     * position @120, its damping @152; 160 bytes */
    assert_int_equal(o.at, 160);
    raw_write(&w, &o);
    await_commands((unsigned)head, 2);
    assert_int_equal(roz_fake_ros2_command(&fake, (unsigned)head, &c), 1);
    assert_int_equal(c.sec, 1700000600);
    assert_int_equal(c.nanosec, 42);
    assert_int_equal(c.seq, 77);
    assert_string_equal(c.frame_id, "f");
    assert_int_equal(c.n, 2);
    for (unsigned i = 0; i < 2; i++) {
        assert_string_equal(c.name[i], x2_head[i]);
        assert_true(c.q[i] == 0.0 + i + 0.25);
        assert_true(c.dq[i] == 10.0 + i + 0.25);
        assert_true(c.tau[i] == 20.0 + i + 0.25);
        assert_true(c.kp[i] == 30.0 + i + 0.25);
        assert_true(c.kd[i] == 40.0 + i + 0.25);
    }
    raw_close(&w);
}

/* ---- the operator: /cmd_vel and /joy ------------------------------------------------------ */

/* geometry_msgs/Twist: Vector3 linear, angular: six float64 @0..40, 48
 * bytes; under ROS 2's names (rt/cmd_vel, geometry_msgs::msg::dds_::Twist_). */
static void test_operator_twist_bytes(void **st)
{
    uint8_t buf[256];
    (void)st;
    start("pm01", NULL);
    dds_entity_t r = wire_reader(&geometry_msgs_msg_dds__Twist__desc, "rt/cmd_vel");
    (void)take_asked(r, "twist 0 0 0 0 0 0", buf, sizeof buf); /* discovery */
    drain(r);
    size_t n = take_asked(r, "twist 0.5 -0.25 1e-3 2 -3 0.125", buf, sizeof buf);
    cdr_t c = { buf + 4, n - 4, 0 };
    static const double v[6] = { 0.5, -0.25, 1e-3, 2, -3, 0.125 };
    assert_int_equal(c.n, 48);
    for (unsigned k = 0; k < 6; k++)
        expect_f64_at(&c, 8 * k, v[k]);
    dds_delete(r);
}

/* sensor_msgs/Joy: Header header (frame_id "joy": length 4 @8, its bytes
 * @12..15); float32[] axes: count @16, values @20 + 4i; int32[] buttons:
 * count after them, values 4 apart. 6 axes, 21 buttons: axes to 44,
 * buttons' count @44, values @48 + 4i, 132 bytes. */
static void test_operator_joy_bytes(void **st)
{
    uint8_t buf[512];
    char id[16];
    (void)st;
    start("x2", NULL);
    dds_entity_t r = wire_reader(&sensor_msgs_msg_dds__Joy__desc, "rt/joy");
    (void)take_asked(r, "joy", buf, sizeof buf);
    drain(r);
    ask("joy_axis 1 0.75");
    ask("joy_axis 5 -1");
    ask("joy_button 0 1");
    ask("joy_button 20 1");
    size_t n = take_asked(r, "joy", buf, sizeof buf);
    cdr_t c = { buf + 4, n - 4, 0 };
    assert_int_equal(c.n, 132);
    assert_true((int32_t)le(&c, 0, 4) >= 1700000000);
    assert_true((uint32_t)le(&c, 4, 4) <= 999999999u);
    c.at = 8;
    cdr_string(&c, id, sizeof id);
    assert_string_equal(id, "joy");
    expect_at(&c, 16);
    assert_int_equal(le(&c, 16, 4), 6);
    for (unsigned i = 0; i < 6; i++) {
        float want = i == 1 ? 0.75f : i == 5 ? -1.0f : 0.0f;
        uint32_t bits;
        memcpy(&bits, &want, sizeof bits);
        assert_int_equal(le(&c, 20 + 4 * i, 4), bits);
    }
    assert_int_equal(le(&c, 44, 4), 21);
    for (unsigned i = 0; i < 21; i++)
        assert_int_equal(le(&c, 48 + 4 * i, 4), i == 0 || i == 20 ? 1 : 0);
    dds_delete(r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_teardown(test_pm01_joint_state_bytes, teardown),
        cmocka_unit_test_teardown(test_pm01_imu_bytes, teardown),
        cmocka_unit_test_teardown(test_x2_joint_state_bytes, teardown),
        cmocka_unit_test_teardown(test_x2_docs_joint_state_bytes, teardown),
        cmocka_unit_test_teardown(test_x2_imu_bytes, teardown),
        cmocka_unit_test_teardown(test_pm01_command_as_written, teardown),
        cmocka_unit_test_teardown(test_x2_command_as_written, teardown),
        cmocka_unit_test_teardown(test_operator_twist_bytes, teardown),
        cmocka_unit_test_teardown(test_operator_joy_bytes, teardown),
    };
    return cmocka_run_group_tests(tests, setup_dds, teardown_dds);
}
