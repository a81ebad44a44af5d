/* SPDX-License-Identifier: Apache-2.0 */
/* roz's own bounded formatter (roz/format.h): the subset of printf that
 * roz's messages use, the same text on every target and C library. */
#include "roz/format.h"

#include <stdint.h>
#include <string.h>

#include "format_internal.h"

/* ---- private: output ------------------------------------------------------ */

typedef struct {
    char  *buf;
    size_t len; /* capacity, with the terminating NUL */
    size_t n;   /* characters the whole text has so far (some may be cut) */
} out_t;

static void put(out_t *o, char ch)
{
    if (o->n + 1u < o->len)
        o->buf[o->n] = ch;
    o->n++;
}

static void repeat(out_t *o, char ch, size_t k)
{
    while (k-- > 0u)
        put(o, ch);
}

/* s[0..n) in a field of `width`: left-justified, or right-justified with
 * spaces, or with zeros after a leading sign. */
static void field(out_t *o, const char *s, size_t n, size_t width, int left, int zero)
{
    size_t fill = width > n ? width - n : 0u;

    if (left) {
        for (size_t i = 0; i < n; i++)
            put(o, s[i]);
        repeat(o, ' ', fill);
        return;
    }
    if (zero) {
        if (n > 0u && s[0] == '-') {
            put(o, '-');
            s++;
            n--;
        }
        repeat(o, '0', fill);
    } else {
        repeat(o, ' ', fill);
    }
    for (size_t i = 0; i < n; i++)
        put(o, s[i]);
}

/* ---- private: numbers ----------------------------------------------------- */

/* Digits of v in base 10 or 16 at the end of d[24]; returns where they start. */
static char *digits(char d[24], uintmax_t v, unsigned base, int upper)
{
    const char *set = upper ? "0123456789ABCDEF" : "0123456789abcdef";
    char *p = d + 24;
    do {
        *--p = set[v % base];
        v /= base;
    } while (v != 0u);
    return p;
}

#if ROZ_CFG_FORMAT_DOUBLE
/* 10^k as a double: exact for 0 <= k <= 22 (every factor and product is a
 * power of ten below 2^53 times a power of two). */
static double pow10i(int k)
{
    double r = 1.0, b = 10.0;
    for (unsigned u = (unsigned)k; u != 0u; u >>= 1) {
        if (u & 1u)
            r *= b;
        b *= b;
    }
    return r;
}

/* x * 10^k for k >= 0, in two steps where 10^k alone would overflow (a
 * value near the smallest doubles). */
static double scale_up(double x, int k)
{
    if (k > 280)
        return x * pow10i(280) * pow10i(k - 280);
    return x * pow10i(k);
}

/* The rounding error of a * b: a * b == p + the result exactly (Dekker's
 * product, plain double arithmetic, no fused multiply-add needed), for
 * |a|, |b| far from overflow. */
static double product_error(double a, double b, double p)
{
    const double split = 134217729.0; /* 2^27 + 1 */
    double ca = split * a, cb = split * b;
    double ah = ca - (ca - a), al = a - ah;
    double bh = cb - (cb - b), bl = b - bh;
    return ((ah * bh - p) + ah * bl + al * bh) + al * bl;
}

size_t roz__format_layout_g(char *s, const char *ds, int prec, int e)
{
    size_t n = 0;
    /* significant digits without trailing zeros (at least one) */
    size_t sig = (size_t)prec;
    while (sig > 1u && ds[sig - 1u] == '0')
        sig--;
    if (e < -4 || e >= prec) {
        s[n++] = ds[0];
        if (sig > 1u) {
            s[n++] = '.';
            memcpy(s + n, ds + 1, sig - 1u);
            n += sig - 1u;
        }
        s[n++] = 'e';
        s[n++] = e < 0 ? '-' : '+';
        unsigned ae = (unsigned)(e < 0 ? -e : e);
        if (ae >= 100u)
            s[n++] = (char)('0' + ae / 100u);
        s[n++] = (char)('0' + ae / 10u % 10u);
        s[n++] = (char)('0' + ae % 10u);
    } else if (e >= 0) {
        memcpy(s + n, ds, (size_t)e + 1u);
        n += (size_t)e + 1u;
        if (sig > (size_t)e + 1u) {
            s[n++] = '.';
            memcpy(s + n, ds + e + 1, sig - ((size_t)e + 1u));
            n += sig - ((size_t)e + 1u);
        }
    } else {
        s[n++] = '0';
        s[n++] = '.';
        for (int i = -1; i > e; i--)
            s[n++] = '0';
        memcpy(s + n, ds, sig);
        n += sig;
    }
    return n;
}

/* %g of x with `prec` significant digits into s (at least 32 bytes);
 * returns its length. */
static size_t fmt_g(char *s, double x, int prec)
{
    uint64_t bits, u, top = 1;
    size_t n = 0;
    int e = 0;
    char ds[20];

    memcpy(&bits, &x, sizeof bits);
    if (x != x) { /* NaN */
        memcpy(s, "nan", 3);
        return 3;
    }
    if (bits >> 63) {
        s[n++] = '-';
        x = -x;
    }
    if (x > 1.7976931348623157e308) {
        memcpy(s + n, "inf", 3);
        return n + 3;
    }
    for (int i = 0; i < prec; i++)
        top *= 10u; /* 10^prec */
    if (x == 0.0) {
        u = top / 10u;
        e = 0;
        memset(ds, '0', (size_t)prec);
    } else {
        /* the decimal exponent: 10^e <= x < 10^(e+1) */
        if (x >= 1.0) {
            while (e < 308 && x >= pow10i(e + 1))
                e++;
        } else {
            while (e > -330 && scale_up(x, -e) < 1.0)
                e--;
        }
        /* x scaled to prec digits, rounded half to even */
        int sc = prec - 1 - e;
        double v = sc >= 0 ? scale_up(x, sc) : x / pow10i(-sc);
        if (!(v < 1e18))
            v = (double)(top / 10u); /* beyond what a message holds: not reached */
        u = (uint64_t)v;
        double frac = v - (double)u;
        if (frac == 0.5 && sc >= -22 && sc <= 22) {
            /* v is a half-way point; the exact x * 10^sc may lie on
             * either side of it (0.025 is 0.025000000000000001387...) */
            double q = pow10i(sc >= 0 ? sc : -sc);
            double side = sc >= 0 ? product_error(x, q, v)
                                  : -((v * q - x) + product_error(v, q, v * q));
            if (side != 0.0)
                frac = side > 0.0 ? 1.0 : 0.0;
        }
        if (frac > 0.5 || (frac == 0.5 && (u & 1u)))
            u++;
        if (u >= top) { /* 9.999995 -> 10.0000 */
            u /= 10u;
            e++;
        }
        char d[24], *p = digits(d, u, 10, 0);
        size_t nd = (size_t)(d + 24 - p);
        memset(ds, '0', (size_t)prec);
        memcpy(ds + ((size_t)prec - nd), p, nd);
    }
    return n + roz__format_layout_g(s + n, ds, prec, e);
}
#else
/* %g without the decimal conversion (ROZ_CFG_FORMAT_DOUBLE 0): the
 * value's bits, exact and the same on every target. */
static size_t fmt_g(char *s, double x, int prec)
{
    uint64_t bits;
    char d[24], *p;

    (void)prec;
    memcpy(&bits, &x, sizeof bits);
    memcpy(s, "f64:", 4);
    p = digits(d, bits, 16u, 0);
    size_t nd = (size_t)(d + 24 - p);
    memset(s + 4, '0', 16u - nd);
    memcpy(s + 4 + (16u - nd), p, nd);
    return 20;
}
#endif

/* ---- public ---------------------------------------------------------------- */

int roz_vformat(char *buf, size_t len, const char *fmt, va_list ap)
{
    out_t o = { buf, len, 0 };

    while (*fmt != '\0') {
        if (*fmt != '%') {
            put(&o, *fmt++);
            continue;
        }
        fmt++;
        int left = 0, zero = 0, prec = -1;
        size_t width = 0;
        for (;; fmt++) {
            if (*fmt == '-')
                left = 1;
            else if (*fmt == '0')
                zero = 1;
            else
                break;
        }
        if (*fmt == '*') {
            int w = va_arg(ap, int);
            if (w < 0) {
                left = 1;
                w = -w;
            }
            width = (size_t)w;
            fmt++;
        } else {
            while (*fmt >= '0' && *fmt <= '9')
                width = width * 10u + (size_t)(*fmt++ - '0');
        }
        if (*fmt == '.') {
            fmt++;
            prec = 0;
            if (*fmt == '*') {
                prec = va_arg(ap, int);
                fmt++;
            } else {
                while (*fmt >= '0' && *fmt <= '9')
                    prec = prec * 10 + (*fmt++ - '0');
            }
        }
        /* length: 0 int, 1 hh, 2 h, 3 l, 4 ll, 5 z, 6 j, 7 t */
        int lm = 0;
        switch (*fmt) {
        case 'h': lm = 2; fmt++; if (*fmt == 'h') { lm = 1; fmt++; } break;
        case 'l': lm = 3; fmt++; if (*fmt == 'l') { lm = 4; fmt++; } break;
        case 'z': lm = 5; fmt++; break;
        case 'j': lm = 6; fmt++; break;
        case 't': lm = 7; fmt++; break;
        default: break;
        }
        char conv = *fmt;
        if (conv != '\0')
            fmt++;
        char d[24], *p;
        switch (conv) {
        case 'd':
        case 'i': {
            intmax_t v;
            switch (lm) {
            case 1: v = (signed char)va_arg(ap, int); break;
            case 2: v = (short)va_arg(ap, int); break;
            case 3: v = va_arg(ap, long); break;
            case 4: v = va_arg(ap, long long); break;
            case 5: v = va_arg(ap, ptrdiff_t); break; /* the signed size_t */
            case 6: v = va_arg(ap, intmax_t); break;
            case 7: v = va_arg(ap, ptrdiff_t); break;
            default: v = va_arg(ap, int); break;
            }
            uintmax_t mag = v < 0 ? (uintmax_t)0 - (uintmax_t)v : (uintmax_t)v;
            p = digits(d, mag, 10, 0);
            if (v < 0)
                *--p = '-';
            field(&o, p, (size_t)(d + 24 - p), width, left, zero);
            break;
        }
        case 'u':
        case 'x':
        case 'X': {
            uintmax_t v;
            switch (lm) {
            case 1: v = (unsigned char)va_arg(ap, unsigned); break;
            case 2: v = (unsigned short)va_arg(ap, unsigned); break;
            case 3: v = va_arg(ap, unsigned long); break;
            case 4: v = va_arg(ap, unsigned long long); break;
            case 5: v = va_arg(ap, size_t); break;
            case 6: v = va_arg(ap, uintmax_t); break;
            case 7: v = (uintmax_t)va_arg(ap, ptrdiff_t); break;
            default: v = va_arg(ap, unsigned); break;
            }
            p = digits(d, v, conv == 'u' ? 10u : 16u, conv == 'X');
            field(&o, p, (size_t)(d + 24 - p), width, left, zero);
            break;
        }
        case 'c':
            d[0] = (char)va_arg(ap, int);
            field(&o, d, 1, width, left, 0);
            break;
        case 's': {
            const char *s = va_arg(ap, const char *);
            size_t n = 0;
            if (s == NULL)
                s = "(null)";
            while ((prec < 0 || n < (size_t)prec) && s[n] != '\0')
                n++;
            field(&o, s, n, width, left, 0);
            break;
        }
        case 'g': {
            char g[40];
            int sig = prec < 0 ? 6 : prec == 0 ? 1 : prec > 15 ? 15 : prec;
            size_t n = fmt_g(g, va_arg(ap, double), sig);
            /* zeros pad a number, never "nan", "inf" or the bits */
            int number = ROZ_CFG_FORMAT_DOUBLE && g[n - 1u] != 'n' && g[n - 1u] != 'f';
            field(&o, g, n, width, left, zero && number);
            break;
        }
        case '%':
            put(&o, '%');
            break;
        default:
            /* not supported: shown, no argument taken */
            put(&o, '%');
            put(&o, '?');
            break;
        }
    }
    if (len > 0u)
        buf[o.n < len ? o.n : len - 1u] = '\0';
    return o.n > (size_t)INT32_MAX ? INT32_MAX : (int)o.n;
}

int roz_format(char *buf, size_t len, const char *fmt, ...)
{
    va_list ap;
    int n;

    va_start(ap, fmt);
    n = roz_vformat(buf, len, fmt, ap);
    va_end(ap);
    return n;
}

