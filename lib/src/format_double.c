/* SPDX-License-Identifier: Apache-2.0 */
/* roz_format_double() (roz/format.h): the shortest text that reads back as a
 * double, from its exact decimal expansion; and roz_text_put_double()
 * (roz/text.h) over it. A file of its own, so that an image that writes no
 * such number links neither it nor strtod. */
#include "roz/format.h"
#include "roz/text.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "format_internal.h"

#if ROZ_CFG_FORMAT_DOUBLE /* else: the bits, at the end of the file */

/* ---- private -------------------------------------------------------------- */

/* A double is m * 2^k, so its decimal expansion is finite: m << k, or
 * m * 5^-k digits with the point moved -k places. Limbs: 2^1024 takes 32,
 * (2^53 - 1) * 5^1074 takes 80; groups of nine digits: 767 digits at most. */
#define BIG_LIMBS 84
#define BIG_GROUPS 90
#define SIG_KEPT 19 /* significant digits kept; beyond them only "any non-zero" */

typedef struct {
    uint32_t w[BIG_LIMBS];
    size_t   n;
} big_t;

static void big_mul_small(big_t *b, uint32_t f)
{
    uint64_t carry = 0;
    for (size_t i = 0; i < b->n; i++) {
        uint64_t v = (uint64_t)b->w[i] * f + carry;
        b->w[i] = (uint32_t)v;
        carry = v >> 32;
    }
    if (carry != 0u)
        b->w[b->n++] = (uint32_t)carry;
}

static void big_shl(big_t *b, unsigned k)
{
    size_t words = k / 32u;
    unsigned bits = k % 32u;
    if (bits != 0u) {
        uint32_t carry = 0;
        for (size_t i = 0; i < b->n; i++) {
            uint32_t v = b->w[i];
            b->w[i] = (v << bits) | carry;
            carry = v >> (32u - bits);
        }
        if (carry != 0u)
            b->w[b->n++] = carry;
    }
    if (words != 0u) {
        memmove(b->w + words, b->w, b->n * sizeof b->w[0]);
        memset(b->w, 0, words * sizeof b->w[0]);
        b->n += words;
    }
}

static uint32_t big_div_1e9(big_t *b)
{
    uint64_t rem = 0;
    for (size_t i = b->n; i-- > 0;) {
        uint64_t cur = (rem << 32) | b->w[i];
        b->w[i] = (uint32_t)(cur / 1000000000u);
        rem = cur % 1000000000u;
    }
    while (b->n > 0u && b->w[b->n - 1u] == 0u)
        b->n--;
    return (uint32_t)rem;
}

/* The first SIG_KEPT significant digits of finite x > 0 into sig (fewer when
 * the expansion is shorter: *nsig), whether any digit after them is non-zero
 * (*sticky), and the decimal exponent of the first (*e10). */
static void exact_digits(double x, char sig[SIG_KEPT], size_t *nsig, int *sticky, int *e10)
{
    big_t b;
    uint32_t groups[BIG_GROUPS];
    size_t ng = 0, total, k = 0;
    int ex;
    double f = frexp(x, &ex); /* x = f * 2^ex, 0.5 <= f < 1 */
    uint64_t m = (uint64_t)ldexp(f, 53);
    int kexp = ex - 53;

    while ((m & 1u) == 0u) { /* fewer digits to carry */
        m >>= 1;
        kexp++;
    }
    b.w[0] = (uint32_t)m;
    b.w[1] = (uint32_t)(m >> 32);
    b.n = b.w[1] != 0u ? 2u : 1u;
    if (kexp >= 0) {
        big_shl(&b, (unsigned)kexp);
    } else {
        for (int i = 0; i < -kexp; i += 13)
            big_mul_small(&b, -kexp - i >= 13 ? 1220703125u /* 5^13 */ : 1u);
        for (int i = 0; i < (-kexp) % 13; i++)
            big_mul_small(&b, 5u);
    }
    while (b.n > 0u)
        groups[ng++] = big_div_1e9(&b);
    /* digits of the top group, then nine per group */
    char top[9];
    size_t nt = 0;
    for (uint32_t g = groups[ng - 1u]; g != 0u; g /= 10u)
        top[nt++] = (char)('0' + g % 10u);
    total = nt + 9u * (ng - 1u);
    *e10 = (int)total - 1 + (kexp < 0 ? kexp : 0);
    *sticky = 0;
    for (size_t i = 0; i < nt; i++) {
        char d = top[nt - 1u - i];
        if (k < SIG_KEPT)
            sig[k++] = d;
        else
            *sticky |= d != '0';
    }
    for (size_t gi = ng - 1u; gi-- > 0;) {
        uint32_t g = groups[gi];
        char d9[9];
        for (int i = 8; i >= 0; i--) {
            d9[i] = (char)('0' + g % 10u);
            g /= 10u;
        }
        for (int i = 0; i < 9; i++) {
            if (k < SIG_KEPT)
                sig[k++] = d9[i];
            else
                *sticky |= d9[i] != '0';
        }
    }
    *nsig = k;
}

/* The exact digits rounded (half to even) to prec <= 17 digits into ds;
 * returns the exponent of the first, one more when it carried (9.99 -> 10.0). */
static int round_digits(const char *sig, size_t nsig, int sticky, int e10, int prec, char *ds)
{
    size_t p = (size_t)prec;
    for (size_t i = 0; i < p; i++)
        ds[i] = i < nsig ? sig[i] : '0';
    if (nsig <= p)
        return e10;
    int rest = sticky;
    for (size_t i = p + 1u; i < nsig; i++)
        rest |= sig[i] != '0';
    char d = sig[p];
    if (d > '5' || (d == '5' && (rest || ((ds[p - 1u] - '0') & 1)))) {
        size_t i = p;
        while (i > 0u && ds[i - 1u] == '9')
            ds[--i] = '0';
        if (i == 0u) {
            ds[0] = '1';
            return e10 + 1;
        }
        ds[i - 1u]++;
    }
    return e10;
}

/* Whether the prec digits ds x 10^e read back as x (strtod is given no
 * decimal point, whose character is the locale's). */
static int reads_back(const char *ds, int prec, int e, double x)
{
    char t[40];
    size_t n = (size_t)prec;
    memcpy(t, ds, n);
    t[n++] = 'e';
    int ex = e - (prec - 1);
    if (ex < 0) {
        t[n++] = '-';
        ex = -ex;
    }
    char d[8];
    size_t nd = 0;
    do {
        d[nd++] = (char)('0' + ex % 10);
        ex /= 10;
    } while (ex != 0);
    while (nd > 0)
        t[n++] = d[--nd];
    t[n] = '\0';
    return strtod(t, NULL) == x;
}

/* ---- public --------------------------------------------------------------- */

int roz_format_double(char *buf, size_t len, double x)
{
    char s[48], sig[SIG_KEPT], ds[20];
    size_t n = 0, nsig = 0;
    int sticky = 0, e10 = 0, prec = 1, e = 0;

    if (x != x) {
        memcpy(s, "nan", 4);
        return roz_format(buf, len, "%s", s);
    }
    if (signbit(x)) {
        s[n++] = '-';
        x = -x;
    }
    if (isinf(x)) {
        memcpy(s + n, "inf", 4);
        return roz_format(buf, len, "%s", s);
    }
    if (x == 0.0) {
        s[n++] = '0';
        s[n] = '\0';
        return roz_format(buf, len, "%s", s);
    }
    exact_digits(x, sig, &nsig, &sticky, &e10);
    for (prec = 1; prec <= 17; prec++) {
        e = round_digits(sig, nsig, sticky, e10, prec, ds);
        if (reads_back(ds, prec, e, x))
            break;
    }
    if (prec > 17)
        prec = 17; /* not reached: 17 digits always read back */
    if ((e < -4 || e >= prec) && e >= 0 && e < 16) {
        /* an integral value below 1e16: written out, every digit exact */
        prec = e + 1;
        e = round_digits(sig, nsig, sticky, e10, prec, ds);
    }
    n += roz__format_layout_g(s + n, ds, prec, e);
    s[n] = '\0';
    return roz_format(buf, len, "%s", s);
}

void roz_text_put_double(roz_text_t *t, double x)
{
    char s[48];
    (void)roz_format_double(s, sizeof s, x);
    roz_text_put(t, s);
    if (strpbrk(s, ".eni") == NULL)
        roz_text_put(t, ".0");
}

#else /* ROZ_CFG_FORMAT_DOUBLE 0: the bits, as %g prints them (format.c) */

int roz_format_double(char *buf, size_t len, double x)
{
    return roz_format(buf, len, "%g", x);
}

void roz_text_put_double(roz_text_t *t, double x)
{
    roz_text_format(t, "%g", x);
}

#endif /* ROZ_CFG_FORMAT_DOUBLE */
