/* SPDX-License-Identifier: Apache-2.0 */
/* The TOML reader (roz/toml.h): every value type, tables and arrays of
 * tables, error positions (those of Python's tomllib, which rozgen uses),
 * refusal of what it does not support, storage exhaustion, no recursion. */
#include <locale.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "roz/toml.h"
#include "support.h"

/* ---- helpers ---------------------------------------------------------------- */

#define NODES 8192u
#define ARENA 4096u

static roz_toml_node_t nodes[NODES];
static char arena[ARENA];
static roz_toml_doc_t doc;
static roz_toml_error_t err;

static int parse(const char *text)
{
    roz_toml_init(&doc, nodes, NODES, arena, ARENA);
    return roz_toml_parse(&doc, text, strlen(text), &err);
}

/* The node at a dotted path of plain keys ("a.b.c"); array elements as
 * numbers ("a.0"). */
static const roz_toml_node_t *at(const char *path)
{
    const roz_toml_node_t *n = roz_toml_root(&doc);
    char part[64];
    while (n != NULL && *path != '\0') {
        size_t len = strcspn(path, ".");
        memcpy(part, path, len);
        part[len] = '\0';
        path += len + (path[len] == '.');
        if (n->type == ROZ_TOML_ARRAY)
            n = roz_toml_at(&doc, n, (size_t)atoi(part));
        else
            n = roz_toml_get(&doc, n, part);
    }
    return n;
}

static int64_t int_at(const char *path)
{
    const roz_toml_node_t *n = at(path);
    assert_non_null(n);
    assert_int_equal(n->type, ROZ_TOML_INTEGER);
    return n->as.integer;
}

static double float_at(const char *path)
{
    const roz_toml_node_t *n = at(path);
    assert_non_null(n);
    assert_int_equal(n->type, ROZ_TOML_FLOAT);
    return n->as.real;
}

static void assert_string_at(const char *path, const char *want, size_t want_len)
{
    const roz_toml_node_t *n = at(path);
    assert_non_null(n);
    assert_int_equal(n->type, ROZ_TOML_STRING);
    assert_int_equal(n->as.str.len, want_len);
    assert_memory_equal(n->as.str.ptr, want, want_len);
}

#define assert_str_at(path, lit) assert_string_at(path, lit, sizeof(lit) - 1)

static void assert_datetime_at(const char *path, roz_toml_type_t type, const char *text)
{
    const roz_toml_node_t *n = at(path);
    char buf[48];
    assert_non_null(n);
    assert_int_equal(n->type, type);
    assert_true(roz_toml_datetime_format(n, buf, sizeof buf) > 0);
    assert_string_equal(buf, text);
}

/* ---- values --------------------------------------------------------------------- */

static void test_toml_strings(void **state)
{
    (void)state;
    assert_int_equal(parse("basic = \"a \\\"q\\\" \\\\ \\b\\t\\n\\f\\r\"\n"
                           "uni = \"\\u00e9 \\U0001F916 \\u0000\"\n"
                           "lit = 'C:\\path \"x\"'\n"
                           "empty = \"\"\n"
                           "ml = \"\"\"\nline 1\nline 2 \\\n    joined\"\"\"\n"
                           "mlq = \"\"\"\"\"two quotes\"\"\"\"\"\n"
                           "mll = '''\nraw \\n ''x'' '''\n"
                           "tab = \"a\tb\"\n"),
                     ROZ_OK);
    assert_str_at("basic", "a \"q\" \\ \b\t\n\f\r");
    assert_str_at("uni", "\xC3\xA9 \xF0\x9F\xA4\x96 \0");
    assert_str_at("lit", "C:\\path \"x\"");
    assert_str_at("empty", "");
    assert_str_at("ml", "line 1\nline 2 joined");
    assert_str_at("mlq", "\"\"two quotes\"\"");
    assert_str_at("mll", "raw \\n ''x'' ");
    assert_str_at("tab", "a\tb");
    /* no escape: the string is the text itself; escapes: the arena */
    assert_true(at("lit")->as.str.ptr > doc.text &&
                at("lit")->as.str.ptr < doc.text + doc.text_len);
    assert_true(at("basic")->as.str.ptr >= arena && at("basic")->as.str.ptr < arena + ARENA);
}

static void test_toml_integers(void **state)
{
    (void)state;
    assert_int_equal(parse("a = 42\nb = +17\nc = -0\nd = 1_000_000\ne = 0xDEAD_beef\n"
                           "f = 0o755\ng = 0b1101_0110\nmax = 9223372036854775807\n"
                           "min = -9223372036854775808\nhmax = 0x7fffffffffffffff\n"),
                     ROZ_OK);
    assert_int_equal(int_at("a"), 42);
    assert_int_equal(int_at("b"), 17);
    assert_int_equal(int_at("c"), 0);
    assert_int_equal(int_at("d"), 1000000);
    assert_int_equal(int_at("e"), 0xDEADBEEF);
    assert_int_equal(int_at("f"), 0755);
    assert_int_equal(int_at("g"), 0xD6);
    assert_true(int_at("max") == INT64_MAX);
    assert_true(int_at("min") == INT64_MIN);
    assert_true(int_at("hmax") == INT64_MAX);
    /* beyond 64 bits: TOML demands an error */
    assert_int_equal(parse("a = 9223372036854775808\n"), ROZ_EINVAL);
    assert_int_equal(parse("a = -9223372036854775809\n"), ROZ_EINVAL);
    assert_int_equal(parse("a = 0x8000000000000000\n"), ROZ_EINVAL);
    assert_int_equal(err.kind, ROZ_TOML_ERR_SYNTAX);
    assert_int_equal(err.column, 5);
    assert_string_equal(err.message, "integer does not fit in 64 bits "
                                     "(-9223372036854775808..9223372036854775807)");
}

static void test_toml_floats(void **state)
{
    (void)state;
    assert_int_equal(parse("a = 3.14\nb = -0.0\nc = 1e6\nd = 6.626e-34\ne = 5E+22\n"
                           "f = 224_617.445_991_228\ng = 1e1_0\nh = inf\ni = -inf\nj = nan\n"
                           "k = +nan\nl = 0.1\nm = 1e400\nn = 5e-324\n"),
                     ROZ_OK);
    assert_true(float_at("a") == 3.14);
    assert_true(float_at("b") == 0.0 && signbit(float_at("b")));
    assert_true(float_at("c") == 1e6);
    assert_true(float_at("d") == 6.626e-34);
    assert_true(float_at("e") == 5e22);
    assert_true(float_at("f") == 224617.445991228);
    assert_true(float_at("g") == 1e10);
    assert_true(isinf(float_at("h")) && float_at("h") > 0);
    assert_true(isinf(float_at("i")) && float_at("i") < 0);
    assert_true(isnan(float_at("j")) && isnan(float_at("k")));
    assert_true(float_at("l") == 0.1);
    assert_true(isinf(float_at("m"))); /* as Python's float() */
    assert_true(float_at("n") == 5e-324);
}

/* The C locale decides strtod's decimal point; a host may have set another. */
static void test_toml_floats_any_locale(void **state)
{
    static const char *const locales[] = { "de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8",
                                           "C.UTF-8" };
    (void)state;
    for (size_t i = 0; i < sizeof locales / sizeof locales[0]; i++) {
        if (setlocale(LC_NUMERIC, locales[i]) == NULL)
            continue;
        assert_int_equal(parse("a = 2.5\nb = 1_0.2_5e1\n"), ROZ_OK);
        assert_true(float_at("a") == 2.5);
        assert_true(float_at("b") == 102.5);
    }
    setlocale(LC_NUMERIC, "C");
}

static void test_toml_bools_and_datetimes(void **state)
{
    (void)state;
    assert_int_equal(parse("t = true\nf = false\n"
                           "odt1 = 1979-05-27T07:32:00Z\n"
                           "odt2 = 1979-05-27T00:32:00.999999-07:00\n"
                           "odt3 = 1979-05-27 07:32:00+05:30\n"
                           "ldt = 1979-05-27t07:32:00.1234567891\n"
                           "ld = 2000-02-29\n"
                           "lt = 00:32:00.5\n"),
                     ROZ_OK);
    assert_int_equal(at("t")->type, ROZ_TOML_BOOL);
    assert_int_equal(at("t")->as.boolean, 1);
    assert_int_equal(at("f")->as.boolean, 0);
    assert_datetime_at("odt1", ROZ_TOML_DATETIME, "1979-05-27T07:32:00Z");
    assert_datetime_at("odt2", ROZ_TOML_DATETIME, "1979-05-27T00:32:00.999999-07:00");
    assert_datetime_at("odt3", ROZ_TOML_DATETIME, "1979-05-27T07:32:00+05:30");
    assert_datetime_at("ldt", ROZ_TOML_DATETIME_LOCAL, "1979-05-27T07:32:00.123456789");
    assert_datetime_at("ld", ROZ_TOML_DATE_LOCAL, "2000-02-29");
    assert_datetime_at("lt", ROZ_TOML_TIME_LOCAL, "00:32:00.5");
    assert_int_equal(at("odt2")->as.datetime.offset_min, -420);
    assert_int_equal(at("odt2")->as.datetime.nanosecond, 999999000);
    assert_string_equal(roz_toml_type_name(ROZ_TOML_DATETIME_LOCAL), "datetime-local");
    assert_string_equal(roz_toml_type_name(ROZ_TOML_TYPE_COUNT_), "?");
    assert_int_equal(roz_toml_datetime_format(at("t"), (char[48]){ 0 }, 48), ROZ_EINVAL);
    assert_int_equal(roz_toml_datetime_format(at("ld"), (char[8]){ 0 }, 8), ROZ_ENOSPC);
}

static void test_toml_arrays_and_inline_tables(void **state)
{
    (void)state;
    assert_int_equal(parse("a = [1, 2.5, \"x\", [true, [[]]], {k = 'v'}]\n"
                           "b = [\n  1,  # one\n\n  2, # two\n]\n"
                           "c = []\n"
                           "t = {x = 1, y.z = 2, w = {}}\n"),
                     ROZ_OK);
    assert_int_equal(roz_toml_count(at("a")), 5);
    assert_int_equal(int_at("a.0"), 1);
    assert_true(float_at("a.1") == 2.5);
    assert_str_at("a.2", "x");
    assert_int_equal(at("a.3.0")->as.boolean, 1);
    assert_int_equal(roz_toml_count(at("a.3.1")), 1);
    assert_int_equal(roz_toml_count(at("a.3.1.0")), 0);
    assert_str_at("a.4.k", "v");
    assert_int_equal(roz_toml_count(at("b")), 2);
    assert_int_equal(int_at("b.1"), 2);
    assert_int_equal(at("c")->type, ROZ_TOML_ARRAY);
    assert_int_equal(roz_toml_count(at("c")), 0);
    assert_int_equal(int_at("t.y.z"), 2);
    assert_int_equal(at("t.w")->type, ROZ_TOML_TABLE);
    assert_null(roz_toml_at(&doc, at("a"), 5));
}

static void test_toml_tables(void **state)
{
    const roz_toml_node_t *root, *c;
    (void)state;
    assert_int_equal(parse("top = 0\n"
                           "fruit.apple.color = \"red\"\n"
                           "[a.b.c]\nx = 1\n"
                           "[a]\ny = 2\nb.z = 3\n"
                           "[[arr]]\nn = 1\n[arr.sub]\nq = 1\n"
                           "[[arr]]\nn = 2\n[[arr.list]]\nm = 1\n"
                           "[\"quoted key\".'lit' . bare]\nk = 1\n"
                           "[fruit.apple.texture]\nsmooth = true\n"),
                     ROZ_OK);
    root = roz_toml_root(&doc);
    assert_int_equal(int_at("a.b.c.x"), 1);
    assert_int_equal(int_at("a.y"), 2);
    assert_int_equal(int_at("a.b.z"), 3);
    assert_int_equal(roz_toml_count(at("arr")), 2);
    assert_int_equal(int_at("arr.0.sub.q"), 1);
    assert_null(at("arr.1.sub"));
    assert_int_equal(int_at("arr.1.list.0.m"), 1);
    assert_int_equal(at("fruit.apple.texture.smooth")->as.boolean, 1);
    assert_non_null(roz_toml_get(&doc, roz_toml_get(&doc, root, "quoted key"), "lit"));
    /* document order, parent links */
    c = roz_toml_first(&doc, root);
    assert_memory_equal(c->key.ptr, "top", 3);
    c = roz_toml_next(&doc, c);
    assert_memory_equal(c->key.ptr, "fruit", 5);
    assert_ptr_equal(roz_toml_parent(&doc, at("a.b")), at("a"));
    assert_null(roz_toml_parent(&doc, root));
    assert_null(roz_toml_get(&doc, at("top"), "x"));
    assert_null(roz_toml_get(&doc, root, NULL));
    assert_null(roz_toml_first(&doc, at("top")));
}

static void test_toml_crlf_and_comments(void **state)
{
    (void)state;
    assert_int_equal(parse("# comment\r\na = 1 # c\r\n\r\n[t] # c\r\nb = \"\"\"x\r\ny\"\"\"\r\n"
                           "c = '''p\r\nq'''\r\nd = [\r\n 1, # c\r\n 2\r\n]"),
                     ROZ_OK);
    assert_int_equal(int_at("a"), 1);
    assert_str_at("t.b", "x\ny");
    assert_str_at("t.c", "p\nq");
    assert_int_equal(int_at("t.d.1"), 2);
    assert_int_equal(parse(""), ROZ_OK);
    assert_int_equal(roz_toml_count(roz_toml_root(&doc)), 0);
}

/* Nesting follows parent links, not the C stack; ROZ_TOML_MAX_DEPTH levels
 * are read (rozgen reads as many), one more is refused at its bracket. */
static void test_toml_deep_nesting(void **state)
{
    static char text[8 * ROZ_TOML_MAX_DEPTH + 64];
    size_t n;
    const roz_toml_node_t *v;
    (void)state;
    /* a = [{k=[{k= ... 1 ... }]}]: ROZ_TOML_MAX_DEPTH levels */
    n = (size_t)sprintf(text, "a = ");
    for (int i = 0; i < ROZ_TOML_MAX_DEPTH / 2; i++)
        n += (size_t)sprintf(text + n, "[{k=");
    n += (size_t)sprintf(text + n, "1");
    for (int i = 0; i < ROZ_TOML_MAX_DEPTH / 2; i++)
        n += (size_t)sprintf(text + n, "}]");
    assert_int_equal(parse(text), ROZ_OK);
    v = at("a");
    for (int i = 0; i < ROZ_TOML_MAX_DEPTH / 2; i++)
        v = roz_toml_get(&doc, roz_toml_first(&doc, v), "k");
    assert_non_null(v);
    assert_int_equal(v->as.integer, 1);

    /* one level more, empty or not, in an array or an inline table */
    static const char *const deepest[] = { "[]", "[1]", "{}", "{x=1}" };
    for (size_t k = 0; k < sizeof deepest / sizeof deepest[0]; k++) {
        n = (size_t)sprintf(text, "ok = [[1]]\nb = ");
        for (int i = 0; i < ROZ_TOML_MAX_DEPTH; i++)
            n += (size_t)sprintf(text + n, "[");
        n += (size_t)sprintf(text + n, "%s", deepest[k]);
        for (int i = 0; i < ROZ_TOML_MAX_DEPTH; i++)
            n += (size_t)sprintf(text + n, "]");
        assert_int_equal(parse(text), ROZ_ENOTSUP);
        assert_int_equal(err.kind, ROZ_TOML_ERR_UNSUPPORTED);
        assert_int_equal(err.line, 2);
        assert_int_equal(err.column, 5 + ROZ_TOML_MAX_DEPTH);
        assert_non_null(strstr(err.message, "nested more than 100 deep"));
    }
    /* depth counts what is open, not what was opened before */
    static char wide[3 * ROZ_TOML_MAX_DEPTH * 16 + 16];
    n = (size_t)sprintf(wide, "a = [");
    for (int i = 0; i < 3 * ROZ_TOML_MAX_DEPTH; i++)
        n += (size_t)sprintf(wide + n, "[[]], {x = {}}, ");
    n += (size_t)sprintf(wide + n, "]");
    assert_true(n < sizeof wide);
    assert_int_equal(parse(wide), ROZ_OK);
    assert_int_equal(roz_toml_count(at("a")), 6 * ROZ_TOML_MAX_DEPTH);
}

/* Many keys in one table: found through the table's key index, duplicates
 * refused wherever they are, document order kept. */
static void test_toml_many_keys(void **state)
{
    enum { KEYS = 5000 };
    static char text[KEYS * 24 + 64];
    char key[16];
    size_t n = 0;
    const roz_toml_node_t *t, *c;
    (void)state;
    /* keys in an order that is neither sorted nor reversed, of mixed lengths */
    n += (size_t)sprintf(text + n, "[t]\n");
    for (int i = 0; i < KEYS; i++)
        n += (size_t)sprintf(text + n, "k%d = %d\n", (i * 7919) % KEYS, i);
    assert_int_equal(parse(text), ROZ_OK);
    t = at("t");
    assert_int_equal(roz_toml_count(t), KEYS);
    for (int i = 0; i < KEYS; i++) {
        sprintf(key, "k%d", (i * 7919) % KEYS);
        c = roz_toml_get(&doc, t, key);
        assert_non_null(c);
        assert_int_equal(c->as.integer, i);
    }
    assert_null(roz_toml_get(&doc, t, "k5000"));
    assert_null(roz_toml_get(&doc, t, "k"));
    assert_null(roz_toml_get(&doc, t, ""));
    c = roz_toml_first(&doc, t); /* document order, not key order */
    for (int i = 0; i < KEYS; i++, c = roz_toml_next(&doc, c))
        assert_int_equal(c->as.integer, i);
    assert_null(c);

    /* a duplicate at the start, the middle and the end of the table, by
     * a plain, a quoted and a dotted key */
    static const char *const dups[] = { "k0 = 1\n", "\"k2500\" = 1\n", "k4999 = 1\n",
                                        "k17.x = 1\n" };
    for (size_t d = 0; d < sizeof dups / sizeof dups[0]; d++) {
        size_t m = n;
        m += (size_t)sprintf(text + m, "%s", dups[d]);
        assert_int_equal(parse(text), ROZ_EINVAL);
        assert_int_equal(err.kind, ROZ_TOML_ERR_SYNTAX);
        assert_int_equal(err.line, KEYS + 2);
        text[n] = '\0';
    }
    assert_non_null(strstr(err.message, "k17"));
    /* keys that differ only in length or in their last byte, and empty keys */
    assert_int_equal(parse("a = 1\naa = 2\nab = 3\n\"\" = 4\n'a\\u0000' = 5\n"), ROZ_OK);
    assert_int_equal(int_at("aa"), 2);
    assert_int_equal(int_at("ab"), 3);
    assert_int_equal(roz_toml_get(&doc, roz_toml_root(&doc), "")->as.integer, 4);
    assert_int_equal(parse("a = 1\naa = 2\n\"\" = 4\n'' = 5\n"), ROZ_EINVAL);
    assert_int_equal(err.line, 4);
    assert_int_equal(parse("a = \"\\u0041\"\n\"\\u0041\" = 1\nA = 2\n"), ROZ_EINVAL);
    assert_int_equal(err.line, 3); /* keys compare decoded */
}

/* ---- errors ------------------------------------------------------------------------ */

/* tomllib's line and column (bytes) for the same mistakes. */
static const struct {
    const char *text;
    uint32_t    line, column;
} syntax_errors[] = {
    { "a = 1\nb = \n", 2, 5 },               /* no value */
    { "a = [1, 2\nb = 3\n", 2, 1 },           /* array not closed */
    { "[t]\nx = 1\n[t]\n", 3, 3 },            /* table twice */
    { "a = 1\na = 2\n", 2, 6 },               /* key twice: just after the value */
    { "a = \"\\q\"\n", 1, 8 },                /* unknown escape: after it */
    { "a = 'open\n", 2, 1 },                  /* literal string never closed: the end */
    { "a = {x = 1,\n y = 2}\n", 1, 12 },      /* inline table over two lines */
    { "a = 0123\n", 1, 6 },                   /* leading zero */
    { "a = 1__0\n", 1, 6 },                   /* double underscore */
    { "a = 2023-02-30\n", 1, 5 },             /* no such date */
    { "a = \"\\uD800\"\n", 1, 12 },           /* a surrogate */
    { "a.b = 1\na.b.c = 2\n", 2, 10 },        /* a dotted key through a value */
    { "x = 1 y = 2\n", 1, 7 },                /* two statements on a line */
    { "[[a]]\n[a]\n", 2, 3 },                 /* array of tables, then table */
    { "a = \"caf\xC3\xA9\" x\n", 1, 13 },     /* columns count bytes */
    { "a = {b = 1}\n[a.c]\n", 2, 5 },         /* inline tables are closed */
    { "a = \"x\r\n", 1, 7 },                  /* CRLF inside a one-line string */
    { "= 1\n", 1, 1 },                        /* no key */
    { "a = \"open", 1, 10 },                  /* the end of the text */
    { "[a\nb = 1\n", 1, 3 },                  /* header not closed */
    { "a = 1\r\nb = 1 2\r\n", 2, 7 },         /* CRLF lines */
    { "\xEF\xBB\xBF" "a = 1\n", 1, 1 },       /* byte order mark */
    { "a = \"\x01\"\n", 1, 6 },               /* control character */
    { "a = 1\rb = 2\n", 1, 6 },               /* lone CR */
};

static void test_toml_error_positions(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof syntax_errors / sizeof syntax_errors[0]; i++) {
        int rc = parse(syntax_errors[i].text);
        if (rc != ROZ_EINVAL || err.kind != ROZ_TOML_ERR_SYNTAX ||
            err.line != syntax_errors[i].line || err.column != syntax_errors[i].column)
            fail_msg("case %zu: rc %d kind %d at %u:%u, want %u:%u (%s)", i, rc, (int)err.kind,
                     (unsigned)err.line, (unsigned)err.column, (unsigned)syntax_errors[i].line,
                     (unsigned)syntax_errors[i].column, err.message);
        assert_true(strlen(err.message) > 0);
        assert_null(roz_toml_root(&doc)); /* an error leaves the document empty */
    }
}

static void test_toml_utf8(void **state)
{
    (void)state;
    assert_int_equal(parse("a = \"\xC3\xA9\"\nb = \"\xE4x\"\n"), ROZ_EINVAL);
    assert_int_equal(err.kind, ROZ_TOML_ERR_UTF8);
    assert_int_equal(err.offset, 14);
    assert_int_equal(err.line, 2);
    assert_int_equal(err.column, 6);
    assert_non_null(strstr(err.message, "0xe4"));
    assert_int_equal(parse("a = \"\xED\xA0\x80\""), ROZ_EINVAL);   /* surrogate */
    assert_int_equal(parse("a = \"\xC0\xAF\""), ROZ_EINVAL);       /* overlong */
    assert_int_equal(parse("a = \"\xF4\x90\x80\x80\""), ROZ_EINVAL); /* > U+10FFFF */
    assert_int_equal(parse("a = \"\xF0\x9F\xA4"), ROZ_EINVAL);     /* cut short */
    assert_int_equal(err.offset, 5);
}

static void test_toml_unsupported(void **state)
{
    (void)state;
    /* valid TOML that the reader refuses (as tomllib does), and says so, at
     * the place where tomllib stops */
    assert_int_equal(parse("t = 23:59:60\n"), ROZ_ENOTSUP);
    assert_int_equal(err.kind, ROZ_TOML_ERR_UNSUPPORTED);
    assert_non_null(strstr(err.message, "leap second"));
    assert_int_equal(err.column, 7);
    assert_int_equal(parse("t = 00:00:60\n"), ROZ_ENOTSUP);
    assert_int_equal(err.column, 6);
    assert_int_equal(parse("t = 1990-12-31T23:59:60Z\n"), ROZ_ENOTSUP);
    assert_int_equal(err.column, 15);
    assert_int_equal(parse("t = [1990-12-31 23:59:60Z]\n"), ROZ_ENOTSUP);
    assert_int_equal(err.column, 17);
    assert_int_equal(parse("t = 1990-02-30T23:59:60Z\n"), ROZ_EINVAL); /* the date first */
    assert_int_equal(err.column, 5);
    assert_int_equal(parse("t = 0000-01-01\n"), ROZ_ENOTSUP);
    assert_int_equal(err.column, 5);
    assert_non_null(strstr(err.message, "year 0000"));
    assert_int_equal(parse("t = 0000-01-01T00:00:00Z\n"), ROZ_ENOTSUP);
    assert_int_equal(parse("t = 0001-01-01T00:00:00Z\n"), ROZ_OK);
}

/* Floats of any length, correctly rounded: the same double as strtod on the
 * whole literal (glibc's strtod is exact for any length). */
static void test_toml_long_floats(void **state)
{
    static char text[12000], lit[11000];
    /* 1 + 2^-53, exactly halfway between 1 and the next double */
    static const char half_one[] = "1.00000000000000011102230246251565404236316680908203125";
    /* 2^-1075, exactly halfway between 0 and the smallest subnormal: 752
     * significant digits after 323 zeros */
    char half_min[1200];
    double want;
    size_t n;
    (void)state;

    /* 2^-1075 = 5^1075 / 10^1075: the digits of 5^1075 by long multiplication */
    {
        unsigned char dig[800];
        size_t len = 1;
        dig[0] = 1;
        for (int k = 0; k < 1075; k++) {
            unsigned carry = 0;
            for (size_t i = 0; i < len; i++) {
                unsigned v = dig[i] * 5u + carry;
                dig[i] = (unsigned char)(v % 10u);
                carry = v / 10u;
            }
            while (carry > 0) {
                dig[len++] = (unsigned char)(carry % 10u);
                carry /= 10u;
            }
        }
        n = (size_t)sprintf(half_min, "0.");
        for (size_t i = len; i < 1075; i++)
            half_min[n++] = '0';
        for (size_t i = len; i-- > 0;)
            half_min[n++] = (char)('0' + dig[i]);
        half_min[n] = '\0';
        assert_true(strtod(half_min, NULL) == 0.0); /* ties to even */
    }

    static const struct {
        const char *head;   /* the literal starts with this */
        size_t      zeros;  /* then this many zeros */
        const char *tail;   /* then this */
    } cases[] = {
        { "0.", 518, "1" },                         /* 521 characters, once misrounded */
        { "0.", 5000, "1" },
        { "1", 3000, ".0" },                        /* inf */
        { "-0.", 600, "1e600" },                    /* 0.1 */
        { "", 0, "" },                              /* half_one, exactly: 1.0 */
        { "", 1000, "1" },                          /* half_one and more: up */
        { "", 0, "" },                              /* half_min, exactly: 0 */
        { "", 200, "1" },                           /* half_min and more: 5e-324 */
        { "9", 900, "e-900" },                      /* 9 */
        { "0.", 900, "e99999999999999999999999" },  /* zero, any exponent */
        { "1_2_3.4_5", 0, "e-1_0" },
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        const char *head = c == 4 || c == 5 ? half_one : c == 6 || c == 7 ? half_min
                                                                           : cases[c].head;
        size_t m = (size_t)sprintf(lit, "%s", head);
        memset(lit + m, '0', cases[c].zeros);
        m += cases[c].zeros;
        m += (size_t)sprintf(lit + m, "%s", cases[c].tail);
        sprintf(text, "f = %s\n", lit);
        assert_int_equal(parse(text), ROZ_OK);
        for (size_t i = 0, k = 0;; i++) { /* strtod does not read underscores */
            if (lit[i] != '_')
                lit[k++] = lit[i];
            if (lit[i] == '\0')
                break;
        }
        want = strtod(lit, NULL);
        if (memcmp(&want, &(double){ float_at("f") }, sizeof want) != 0)
            fail_msg("case %zu: read %.17g, strtod %.17g", c, float_at("f"), want);
    }
    assert_true(float_at("f") == 123.45e-10);
    assert_int_equal(parse("f = -0.0000000000000000000000000000e7\n"), ROZ_OK);
    assert_true(float_at("f") == 0.0 && signbit(float_at("f")));
}

static void test_toml_storage_exhausted(void **state)
{
    static roz_toml_node_t few[4];
    static char tiny[4];
    roz_toml_doc_t d;
    (void)state;
    roz_toml_init(&d, few, 4, tiny, sizeof tiny);
    assert_int_equal(roz_toml_parse(&d, "a = 1\nb = 2\nc = 3\n", 18, &err), ROZ_OK);
    assert_int_equal(d.n_nodes, 4);
    assert_int_equal(roz_toml_parse(&d, "a = 1\nb = 2\nc = 3\nd = 4\n", 24, &err), ROZ_ENOSPC);
    assert_int_equal(err.kind, ROZ_TOML_ERR_NODES);
    assert_int_equal(err.line, 4);
    assert_null(roz_toml_root(&d));
    /* strings without escapes need no arena; with them they do */
    assert_int_equal(roz_toml_parse(&d, "a = \"long string\"\n", 18, &err), ROZ_OK);
    assert_int_equal(roz_toml_parse(&d, "a = \"\\tlong\"\n", 13, &err), ROZ_ENOSPC);
    assert_int_equal(err.kind, ROZ_TOML_ERR_ARENA);
    /* no arena at all */
    roz_toml_init(&d, few, 4, NULL, 0);
    assert_int_equal(roz_toml_parse(&d, "a = 'x'\n", 8, &err), ROZ_OK);
    assert_int_equal(roz_toml_parse(&d, "a = \"\\n\"\n", 9, &err), ROZ_ENOSPC);
    /* no nodes at all */
    roz_toml_init(&d, NULL, 0, NULL, 0);
    assert_int_equal(roz_toml_parse(&d, "", 0, &err), ROZ_ENOSPC);
}

static void test_toml_arguments(void **state)
{
    (void)state;
    assert_int_equal(roz_toml_parse(NULL, "a = 1", 5, &err), ROZ_EINVAL);
    assert_int_equal(err.kind, ROZ_TOML_ERR_ARG);
    roz_toml_init(&doc, nodes, NODES, arena, ARENA);
    assert_int_equal(roz_toml_parse(&doc, NULL, 5, NULL), ROZ_EINVAL);
    assert_int_equal(roz_toml_parse(&doc, NULL, 0, NULL), ROZ_OK); /* empty */
    assert_null(roz_toml_root(NULL));
    assert_int_equal(roz_toml_count(NULL), 0);
    /* the text need not be NUL-terminated: only len bytes are read */
    assert_int_equal(roz_toml_parse(&doc, "a = 12345", 6, &err), ROZ_OK);
    assert_int_equal(int_at("a"), 12);
    roz_toml_init(NULL, nodes, NODES, arena, ARENA); /* no crash */
}

ROZ_TEST_MAIN(cmocka_unit_test(test_toml_strings),
              cmocka_unit_test(test_toml_integers),
              cmocka_unit_test(test_toml_floats),
              cmocka_unit_test(test_toml_floats_any_locale),
              cmocka_unit_test(test_toml_bools_and_datetimes),
              cmocka_unit_test(test_toml_arrays_and_inline_tables),
              cmocka_unit_test(test_toml_tables),
              cmocka_unit_test(test_toml_crlf_and_comments),
              cmocka_unit_test(test_toml_deep_nesting),
              cmocka_unit_test(test_toml_many_keys),
              cmocka_unit_test(test_toml_error_positions),
              cmocka_unit_test(test_toml_utf8),
              cmocka_unit_test(test_toml_unsupported),
              cmocka_unit_test(test_toml_long_floats),
              cmocka_unit_test(test_toml_storage_exhausted),
              cmocka_unit_test(test_toml_arguments))
