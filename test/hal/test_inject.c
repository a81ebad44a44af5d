/* SPDX-License-Identifier: Apache-2.0 */
/* The simulators' fault-injection grammar (roz/hal/inject.h): the entries
 * it hands the port, and the words of what it refuses. The ports' own
 * tests (test_loopback, test_mujoco) hold each port to it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "roz/error.h"
#include "roz/hal/inject.h"
#include "support.h"

#define MAX_GOT 8

static roz_inject_entry_t got[MAX_GOT];
static size_t n_got;
static int answer; /* what the port's callback says */

static int take(void *ctx, const roz_inject_entry_t *e, char *why, size_t whylen)
{
    (void)ctx;
    assert_true(n_got < MAX_GOT);
    got[n_got++] = *e;
    if (answer != ROZ_OK)
        strncpy(why, "the port says no", whylen);
    return answer;
}

static int parse(roz_inject_kind_t kind, const char *value, char *err, size_t errlen)
{
    n_got = 0;
    err[0] = '\0';
    return roz_inject_parse(kind, value, take, NULL, err, errlen);
}

static void test_inject_keys(void **st)
{
    (void)st;
    for (int k = ROZ_INJECT_DROP; k < ROZ_INJECT_KIND_END; k++)
        assert_int_equal(roz_inject_find(roz_inject_key((roz_inject_kind_t)k)), k);
    assert_string_equal(roz_inject_key(ROZ_INJECT_CORRUPT_CMD), "corrupt_cmd");
    assert_int_equal(roz_inject_find("dropp"), 0);
    assert_null(roz_inject_key((roz_inject_kind_t)0));
    assert_null(roz_inject_key(ROZ_INJECT_KIND_END));
}

static void test_inject_entries(void **st)
{
    char err[256];
    (void)st;
    answer = ROZ_OK;
    assert_int_equal(parse(ROZ_INJECT_DROP, "7", err, sizeof err), ROZ_OK);
    assert_int_equal(n_got, 1);
    assert_int_equal(got[0].kind, ROZ_INJECT_DROP);
    assert_true(got[0].from == 7 && got[0].to == 0);
    assert_int_equal(parse(ROZ_INJECT_DELAY, "3@10:20 ; 15@30: ;1@18446744073709551615", err,
                           sizeof err), ROZ_OK);
    assert_int_equal(n_got, 3);
    assert_true(got[0].arg == 3 && got[0].from == 10 && got[0].to == 20);
    assert_true(got[1].arg == 15 && got[1].from == 30 && got[1].to == 0);
    assert_true(got[2].arg == 1 && got[2].from == UINT64_MAX);
    assert_string_equal(got[0].head, "");
    /* the head is before the last '@': a push's body follows its force */
    assert_int_equal(parse(ROZ_INJECT_PUSH, "1,-2,3e1@pelvis@5:6", err, sizeof err), ROZ_OK);
    assert_string_equal(got[0].head, "1,-2,3e1@pelvis");
    assert_int_equal(parse(ROZ_INJECT_NAN, "elbow/position@5:6;0@1:2", err, sizeof err), ROZ_OK);
    assert_int_equal(n_got, 2);
    assert_string_equal(got[0].head, "elbow/position");
    assert_string_equal(got[1].head, "0");
}

static void test_inject_refusals(void **st)
{
    static const struct {
        roz_inject_kind_t kind;
        const char *value, *want;
        size_t taken; /* entries passed on before the refusal */
    } cases[] = {
        { ROZ_INJECT_DROP, "300:100", "parameter drop = \"300:100\": FROM 300 after TO 100", 0 },
        { ROZ_INJECT_DROP, "5:5", "FROM 5 equals TO: the ticks [FROM, TO) are none", 0 },
        { ROZ_INJECT_DROP, "5:0", "FROM 5 after TO 0", 0 },
        { ROZ_INJECT_DROP, "", "FROM is missing or not a tick number; expected FROM:TO (ticks, "
                               "TO empty = forever, ';' between entries)", 0 },
        { ROZ_INJECT_DROP, "1:2;", "parameter drop = \"1:2;\": FROM is missing", 1 },
        { ROZ_INJECT_DROP, "1:2;;3:4", "FROM is missing", 1 },
        { ROZ_INJECT_DROP, "1 :2", "unexpected \" :2\" after the ticks", 0 },
        { ROZ_INJECT_DROP, "+1:2", "FROM is missing or not a tick number", 0 },
        { ROZ_INJECT_DROP, "18446744073709551616", "FROM 18446744073709551616 is too large", 0 },
        { ROZ_INJECT_FREEZE, "1:2@3", "unexpected \"@3\" after the ticks; expected FROM[:TO]", 0 },
        { ROZ_INJECT_RESTART, "5:", "no TO: the robot boots again at TO; expected FROM:TO (ticks, "
                                    "';' between entries)", 0 },
        { ROZ_INJECT_RESTART, "1:2;5", "no TO", 1 },
        { ROZ_INJECT_DELAY, "16@1:2", "K 16 is not a delay in 1..15 ticks; expected K@FROM:TO", 0 },
        { ROZ_INJECT_DELAY, "1:2", "no K before '@'; expected K@FROM:TO", 0 },
        { ROZ_INJECT_NAN, "@1:2", "no CHANNEL before '@'", 0 },
        { ROZ_INJECT_PUSH, "1:2", "no FX,FY,FZ@BODY before '@'", 0 },
        { ROZ_INJECT_NAN,
          "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa@1:2",
          "the CHANNEL before '@' is longer than 95 characters", 0 },
    };
    char err[320];
    (void)st;
    answer = ROZ_OK;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        if (parse(cases[i].kind, cases[i].value, err, sizeof err) != ROZ_EINVAL)
            fail_msg("%s accepted", cases[i].value);
        if (strstr(err, cases[i].want) == NULL)
            fail_msg("\"%s\" lacks \"%s\"", err, cases[i].want);
        if (n_got != cases[i].taken)
            fail_msg("%s: %zu entries taken, not %zu", cases[i].value, n_got, cases[i].taken);
    }
}

/* The port's own refusal: its words, and the form when it is the form's. */
static void test_inject_port_refuses(void **st)
{
    char err[320];
    (void)st;
    answer = ROZ_INJECT_BAD;
    assert_int_equal(parse(ROZ_INJECT_NAN, "x@1:2", err, sizeof err), ROZ_EINVAL);
    assert_string_equal(err, "parameter nan = \"x@1:2\": the port says no");
    answer = ROZ_INJECT_SYNTAX;
    assert_int_equal(parse(ROZ_INJECT_PUSH, "x@b@1:2", err, sizeof err), ROZ_EINVAL);
    assert_non_null(strstr(err, "the port says no; expected FX,FY,FZ@BODY@FROM:TO"));
    answer = ROZ_OK;
    assert_int_equal(roz_inject_parse((roz_inject_kind_t)0, "1:2", take, NULL, err, sizeof err),
                     ROZ_EINVAL);
    assert_int_equal(roz_inject_parse(ROZ_INJECT_DROP, NULL, take, NULL, err, sizeof err),
                     ROZ_EINVAL);
}

ROZ_TEST_MAIN(cmocka_unit_test(test_inject_keys),
              cmocka_unit_test(test_inject_entries),
              cmocka_unit_test(test_inject_refusals),
              cmocka_unit_test(test_inject_port_refuses))
