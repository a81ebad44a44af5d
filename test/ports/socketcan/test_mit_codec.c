/* SPDX-License-Identifier: Apache-2.0 */
/* The MIT-mode codec (roz/port/mit_codec.h) against the vectors of an independent
 * model (mit_model.py: exact rational arithmetic, bit-by-bit layout; the
 * table is mit_vectors.txt, which test_mit_model.py keeps current), then
 * the codec's own properties: every code of every width round-trips
 * exactly, a value comes back within half a step, saturation and non-finite
 * values at every end, the special frames, bad ranges. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "roz/port/mit_codec.h"
#include "support.h"

#ifndef ROZ_CAN_VECTORS
#error "ROZ_CAN_VECTORS: the path of mit_vectors.txt"
#endif

#define MAX_RANGE_SETS 8

typedef struct {
    char             name[16];
    roz_mit_ranges_t r;
} named_ranges_t;

static named_ranges_t range_sets[MAX_RANGE_SETS];
static size_t n_range_sets;

/* ---- reading the table ------------------------------------------------------ */

static double num(const char *s, unsigned line)
{
    char *end;
    double x = strtod(s, &end);
    if (end == s || *end != '\0')
        fail_msg("line %u: \"%s\" is not a number", line, s);
    return x;
}

static long integer(const char *s, unsigned line)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (end == s || *end != '\0')
        fail_msg("line %u: \"%s\" is not an integer", line, s);
    return v;
}

static size_t hex_bytes(const char *s, uint8_t *out, size_t cap, unsigned line)
{
    size_t n = 0;
    if (strcmp(s, "-") == 0)
        return 0;
    for (; s[0] != '\0' && s[1] != '\0'; s += 2) {
        unsigned b = 0;
        if (n == cap || sscanf(s, "%2x", &b) != 1)
            fail_msg("line %u: bad bytes", line);
        out[n++] = (uint8_t)b;
    }
    return n;
}

static const roz_mit_ranges_t *ranges_named(const char *name, unsigned line)
{
    for (size_t i = 0; i < n_range_sets; i++) {
        if (strcmp(range_sets[i].name, name) == 0)
            return &range_sets[i].r;
    }
    fail_msg("line %u: no ranges %s", line, name);
    return NULL;
}

/* Same double, or both NaN. */
static int same(double a, double b)
{
    return (isnan(a) && isnan(b)) || memcmp(&a, &b, sizeof a) == 0;
}

/* A decoded value: exact at the ends, else within 1e-12 of the range. */
static void check_value(double got, double want, uint16_t code, unsigned bits,
                        const roz_mit_range_t *r, unsigned line)
{
    uint32_t top = (1u << bits) - 1u;
    if ((code == 0 || code == top) ? !same(got, want)
                                   : !(fabs(got - want) <= 1e-12 * (r->max - r->min)))
        fail_msg("line %u: code %u decodes to %.17g, model %.17g", line, code, got, want);
}

/* ---- the vectors ------------------------------------------------------------ */

static unsigned counts[6];

static void vector(char **tok, int n, unsigned line)
{
    if (n >= 12 && strcmp(tok[0], "ranges") == 0) {
        if (n_range_sets == MAX_RANGE_SETS)
            fail_msg("line %u: too many range sets", line);
        named_ranges_t *nr = &range_sets[n_range_sets++];
        snprintf(nr->name, sizeof nr->name, "%s", tok[1]);
        roz_mit_range_t *f[5] = { &nr->r.position, &nr->r.velocity, &nr->r.kp, &nr->r.kd,
                                  &nr->r.torque };
        for (int i = 0; i < 5; i++) {
            f[i]->min = num(tok[2 + 2 * i], line);
            f[i]->max = num(tok[3 + 2 * i], line);
        }
        assert_true(roz_mit_codec_ranges_valid(&nr->r));
    } else if (n == 8 && strcmp(tok[0], "encode") == 0) {
        unsigned bits = (unsigned)integer(tok[1], line);
        roz_mit_range_t r = { num(tok[2], line), num(tok[3], line) };
        uint16_t code = 0xDEAD;
        uint32_t what = roz_mit_codec_encode(num(tok[4], line), &r, bits, &code);
        if (code != integer(tok[6], line) || what != (uint32_t)integer(tok[7], line))
            fail_msg("line %u: encode %s in [%s, %s] at %u bits: code %u what %u, model %s %s",
                     line, tok[4], tok[2], tok[3], bits, code, what, tok[6], tok[7]);
        counts[0]++;
    } else if (n == 7 && strcmp(tok[0], "decode") == 0) {
        unsigned bits = (unsigned)integer(tok[1], line);
        roz_mit_range_t r = { num(tok[2], line), num(tok[3], line) };
        uint16_t code = (uint16_t)integer(tok[4], line);
        check_value(roz_mit_codec_decode(code, &r, bits), num(tok[6], line), code, bits, &r,
                    line);
        counts[1]++;
    } else if (n == 10 && strcmp(tok[0], "pack") == 0) {
        const roz_mit_ranges_t *r = ranges_named(tok[1], line);
        roz_mit_command_t c = { num(tok[2], line), num(tok[3], line), num(tok[4], line),
                                num(tok[5], line), num(tok[6], line) };
        uint8_t want[8], got[8];
        assert_int_equal(hex_bytes(tok[8], want, sizeof want, line), 8);
        uint32_t what = roz_mit_codec_pack(r, &c, got);
        if (memcmp(got, want, 8) != 0 || what != (uint32_t)integer(tok[9], line))
            fail_msg("line %u: pack gives %02x%02x%02x%02x%02x%02x%02x%02x what %u, model %s %s",
                     line, got[0], got[1], got[2], got[3], got[4], got[5], got[6], got[7], what,
                     tok[8], tok[9]);
        counts[2]++;
    } else if (n == 15 && strcmp(tok[0], "unpack") == 0) {
        roz_mit_reply_layout_t layout;
        const roz_mit_ranges_t *r = ranges_named(tok[2], line);
        uint8_t data[8];
        size_t len = hex_bytes(tok[3], data, sizeof data, line);
        roz_mit_reply_t rep;
        assert_int_equal(roz_mit_codec_layout_parse(tok[1], &layout), ROZ_OK);
        memset(&rep, 0xA5, sizeof rep);
        int rc = roz_mit_codec_unpack(r, layout, len > 0 ? data : NULL, len, &rep);
        if (rc != integer(tok[5], line))
            fail_msg("line %u: unpack returns %d, model %s", line, rc, tok[5]);
        if (rc == ROZ_OK) {
            if (rep.id != integer(tok[6], line) || rep.position_code != integer(tok[7], line) ||
                rep.velocity_code != integer(tok[8], line) ||
                rep.torque_code != integer(tok[9], line) ||
                rep.temperature != integer(tok[13], line) || rep.error != integer(tok[14], line))
                fail_msg("line %u: unpack: id %u codes %u %u %u temperature %u error %u", line,
                         rep.id, rep.position_code, rep.velocity_code, rep.torque_code,
                         rep.temperature, rep.error);
            check_value(rep.position, num(tok[10], line), rep.position_code,
                        ROZ_MIT_POSITION_BITS, &r->position, line);
            check_value(rep.velocity, num(tok[11], line), rep.velocity_code,
                        ROZ_MIT_VELOCITY_BITS, &r->velocity, line);
            check_value(rep.torque, num(tok[12], line), rep.torque_code, ROZ_MIT_TORQUE_BITS,
                        &r->torque, line);
        }
        counts[3]++;
    } else if (n == 4 && strcmp(tok[0], "special") == 0) {
        uint8_t data[16];
        size_t len = hex_bytes(tok[1], data, sizeof data, line);
        if (roz_mit_codec_special_of(data, len) != integer(tok[3], line))
            fail_msg("line %u: special_of %s is %d, model %s", line, tok[1],
                     roz_mit_codec_special_of(data, len), tok[3]);
        counts[4]++;
    } else {
        fail_msg("line %u: not a vector (%d fields)", line, n);
    }
}

static void test_mit_codec_vectors(void **state)
{
    char buf[1024];
    unsigned line = 0;
    FILE *f = fopen(ROZ_CAN_VECTORS, "r");
    (void)state;
    if (f == NULL)
        fail_msg("cannot read %s", ROZ_CAN_VECTORS);
    while (fgets(buf, sizeof buf, f) != NULL) {
        char *tok[20] = { NULL };
        int n = 0;
        line++;
        if (buf[0] == '#' || buf[0] == '\n')
            continue;
        for (char *t = strtok(buf, " \n"); t != NULL && n < 20; t = strtok(NULL, " \n"))
            tok[n++] = t;
        vector(tok, n, line);
    }
    fclose(f);
    print_message("%u encode, %u decode, %u pack, %u unpack, %u special vectors\n", counts[0],
                  counts[1], counts[2], counts[3], counts[4]);
    for (int k = 0; k < 5; k++)
        assert_true(counts[k] > 0);
}

/* ---- properties ------------------------------------------------------------- */

static const roz_mit_range_t some_ranges[] = {
    { -12.5, 12.5 }, { 0.0, 500.0 }, { -22.5, 10.0 }, { -5.0, -1.0 }, { 0.0, 1e-3 },
    { -95.5, 95.5 }, { 1e5, 1e5 + 1.0 },
};
#define N_SOME (sizeof some_ranges / sizeof some_ranges[0])

static void test_mit_codec_every_code_round_trips(void **state)
{
    (void)state;
    for (size_t k = 0; k < N_SOME; k++) {
        const roz_mit_range_t *r = &some_ranges[k];
        for (unsigned bits = 1; bits <= ROZ_MIT_MAX_BITS; bits++) {
            uint32_t top = (1u << bits) - 1u;
            assert_true(same(roz_mit_codec_decode(0, r, bits), r->min));
            assert_true(same(roz_mit_codec_decode((uint16_t)top, r, bits), r->max));
            for (uint32_t c = 0; c <= top; c++) {
                uint16_t back = 0;
                double x = roz_mit_codec_decode((uint16_t)c, r, bits);
                assert_int_equal(roz_mit_codec_encode(x, r, bits, &back), 0);
                if (back != c)
                    fail_msg("[%g, %g] at %u bits: code %u decodes to %.17g, which encodes to %u",
                             r->min, r->max, bits, c, x, back);
            }
        }
    }
}

static void test_mit_codec_within_half_a_step(void **state)
{
    uint64_t seed = 15;
    (void)state;
    for (size_t k = 0; k < N_SOME; k++) {
        const roz_mit_range_t *r = &some_ranges[k];
        for (unsigned bits = 1; bits <= ROZ_MIT_MAX_BITS; bits++) {
            double half = roz_mit_codec_step(r, bits) / 2.0;
            /* and what the double nearest x may be off by */
            double big = fmax(fabs(r->min), fabs(r->max));
            double slack = 8.0 * (nextafter(big, INFINITY) - big);
            for (int i = 0; i < 2000; i++) {
                uint16_t code;
                seed = seed * 6364136223846793005u + 1442695040888963407u;
                double u = (double)(seed >> 11) / 9007199254740992.0; /* [0, 1) */
                double x = r->min + u * (r->max - r->min);
                assert_int_equal(roz_mit_codec_encode(x, r, bits, &code), 0);
                double err = fabs(roz_mit_codec_decode(code, r, bits) - x);
                if (!(err <= half * (1.0 + 1e-9) + slack))
                    fail_msg("[%g, %g] at %u bits: %.17g comes back %.3g away, half a step is %.3g",
                             r->min, r->max, bits, x, err, half);
            }
        }
    }
}

static void test_mit_codec_saturation_at_every_end_and_width(void **state)
{
    (void)state;
    for (size_t k = 0; k < N_SOME; k++) {
        const roz_mit_range_t *r = &some_ranges[k];
        for (unsigned bits = 1; bits <= ROZ_MIT_MAX_BITS; bits++) {
            uint16_t top = (uint16_t)((1u << bits) - 1u), code;
            assert_int_equal(roz_mit_codec_encode(r->max, r, bits, &code), 0);
            assert_int_equal(code, top);
            assert_int_equal(roz_mit_codec_encode(r->min, r, bits, &code), 0);
            assert_int_equal(code, 0);
            assert_int_equal(roz_mit_codec_encode(nextafter(r->max, INFINITY), r, bits, &code),
                             ROZ_MIT_CODE_SATURATED);
            assert_int_equal(code, top);
            assert_int_equal(roz_mit_codec_encode(nextafter(r->min, -INFINITY), r, bits, &code),
                             ROZ_MIT_CODE_SATURATED);
            assert_int_equal(code, 0);
            assert_int_equal(roz_mit_codec_encode(-1e300, r, bits, &code),
                             ROZ_MIT_CODE_SATURATED);
            assert_int_equal(code, 0);
            double nz = r->min > 0 ? r->min : r->max < 0 ? r->max : 0.0;
            uint16_t want;
            assert_int_equal(roz_mit_codec_encode(nz, r, bits, &want), 0);
            assert_int_equal(roz_mit_codec_encode(NAN, r, bits, &code), ROZ_MIT_CODE_NONFINITE);
            assert_int_equal(code, want);
            assert_int_equal(roz_mit_codec_encode(-INFINITY, r, bits, &code),
                             ROZ_MIT_CODE_NONFINITE);
            assert_int_equal(code, want);
        }
    }
}

static void test_mit_codec_pack_reports_each_field(void **state)
{
    const roz_mit_ranges_t r = { { -12.5, 12.5 }, { -45, 45 }, { 0, 500 }, { 0, 5 }, { -18, 18 } };
    roz_mit_command_t c = { 0, 0, 0, 0, 0 };
    uint8_t f[8];
    (void)state;
    assert_int_equal(roz_mit_codec_pack(&r, &c, f), 0);
    c.position = 13;
    assert_int_equal(roz_mit_codec_pack(&r, &c, f), ROZ_MIT_SAT_POSITION);
    c = (roz_mit_command_t){ 0, -46, 501, -1, 18.5 };
    assert_int_equal(roz_mit_codec_pack(&r, &c, f),
                     ROZ_MIT_SAT_VELOCITY | ROZ_MIT_SAT_KP | ROZ_MIT_SAT_KD | ROZ_MIT_SAT_TORQUE);
    /* a NaN position sends kp's lowest code; a NaN velocity kd's */
    c = (roz_mit_command_t){ NAN, INFINITY, 400, 4, NAN };
    assert_int_equal(roz_mit_codec_pack(&r, &c, f), ROZ_MIT_NONFINITE_POSITION |
                                                         ROZ_MIT_NONFINITE_VELOCITY |
                                                         ROZ_MIT_NONFINITE_TORQUE);
    assert_int_equal(((f[3] & 0x0Fu) << 8) | f[4], 0);
    assert_int_equal((f[5] << 4) | (f[6] >> 4), 0);
    /* the top of everything with torque just below its top reads as no
     * special frame */
    roz_mit_codes_t codes = { 0xFFFF, 0xFFF, 0xFFF, 0xFFF, 0xFFD };
    assert_int_equal(roz_mit_codec_pack_codes(&codes, f), ROZ_MIT_AVOIDED_SPECIAL);
    assert_int_equal(roz_mit_codec_special_of(f, 8), 0);
    assert_int_equal(f[7], 0xFB);
}

static void test_mit_codec_special_frames(void **state)
{
    static const roz_mit_special_t kinds[] = { ROZ_MIT_ENTER_MOTOR_MODE, ROZ_MIT_EXIT_MOTOR_MODE,
                                               ROZ_MIT_SET_ZERO };
    uint8_t f[8];
    (void)state;
    for (size_t i = 0; i < 3; i++) {
        roz_mit_codec_special(kinds[i], f);
        for (int b = 0; b < 7; b++)
            assert_int_equal(f[b], 0xFF);
        assert_int_equal(f[7], kinds[i]);
        assert_int_equal(roz_mit_codec_special_of(f, 8), kinds[i]);
        assert_int_equal(roz_mit_codec_special_of(f, 7), 0);
    }
    assert_int_equal(roz_mit_codec_special_of(NULL, 8), 0);
}

static void test_mit_codec_bad_ranges_and_layouts(void **state)
{
    const roz_mit_range_t bad[] = { { 1, 1 }, { 2, 1 }, { NAN, 1 }, { 0, INFINITY },
                                    { -1e308, 1e308 }, { 0, 1e305 } };
    roz_mit_ranges_t r = { { -1, 1 }, { -1, 1 }, { 0, 1 }, { 0, 1 }, { -1, 1 } };
    roz_mit_reply_layout_t layout;
    roz_mit_reply_t rep, untouched;
    uint8_t data[8] = { 1, 2, 3, 4, 5, 6, 7, 8 };
    (void)state;
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        assert_false(roz_mit_codec_range_valid(&bad[i]));
    assert_true(roz_mit_codec_ranges_valid(&r));
    r.kd = bad[0];
    assert_false(roz_mit_codec_ranges_valid(&r));
    assert_false(roz_mit_codec_ranges_valid(NULL));

    assert_string_equal(roz_mit_codec_layout_name(ROZ_MIT_REPLY_BASIC), "basic");
    assert_string_equal(roz_mit_codec_layout_name(ROZ_MIT_REPLY_TEMP_ERROR), "temperature_error");
    assert_null(roz_mit_codec_layout_name(ROZ_MIT_REPLY_LAYOUT_COUNT_));
    assert_int_equal(roz_mit_codec_layout_parse("temperature_error", &layout), ROZ_OK);
    assert_int_equal(layout, ROZ_MIT_REPLY_TEMP_ERROR);
    assert_int_equal(roz_mit_codec_layout_parse("Basic", &layout), ROZ_EINVAL);
    assert_int_equal(roz_mit_codec_reply_bytes(ROZ_MIT_REPLY_BASIC), 6);
    assert_int_equal(roz_mit_codec_reply_bytes(ROZ_MIT_REPLY_TEMP_ERROR), 8);

    memset(&rep, 0x5A, sizeof rep);
    untouched = rep;
    assert_int_equal(roz_mit_codec_unpack(&r, ROZ_MIT_REPLY_TEMP_ERROR, data, 7, &rep),
                     ROZ_EINVAL);
    assert_int_equal(roz_mit_codec_unpack(&r, ROZ_MIT_REPLY_LAYOUT_COUNT_, data, 8, &rep),
                     ROZ_EINVAL);
    assert_memory_equal(&rep, &untouched, sizeof rep);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_mit_codec_vectors),
              cmocka_unit_test(test_mit_codec_every_code_round_trips),
              cmocka_unit_test(test_mit_codec_within_half_a_step),
              cmocka_unit_test(test_mit_codec_saturation_at_every_end_and_width),
              cmocka_unit_test(test_mit_codec_pack_reports_each_field),
              cmocka_unit_test(test_mit_codec_special_frames),
              cmocka_unit_test(test_mit_codec_bad_ranges_and_layouts))
