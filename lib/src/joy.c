/* SPDX-License-Identifier: Apache-2.0 */
/* A Joy as the remote (roz/joy.h): a map read once at start-up, applied to
 * each message on its reader's thread. The rule of every Joy map lives here
 * only. */
#include "roz/joy.h"

#include <math.h>
#include <string.h>

#include "roz/error.h"
#include "roz/format.h"

#define ENTRY_MAX 48 /* longer than any valid entry ("btn.select=-a31") */

static int is_remote(roz_operator_field_t f)
{
    return roz_operator_field_device(f) == ROZ_OPERATOR_DEVICE_REMOTE;
}

static int is_button(roz_operator_field_t f)
{
    return f >= ROZ_OPERATOR_REMOTE_BTN_R1 && f <= ROZ_OPERATOR_REMOTE_BTN_LEFT;
}

/* "aN", "-aN", "bN": N decimal, < ROZ_JOY_MAX, no leading zero */
static int parse_source(const char *s, size_t len, roz_joy_source_t *src)
{
    size_t i = 0;
    unsigned n = 0;
    src->sign = 1;
    if (i < len && s[i] == '-') {
        src->sign = -1;
        i++;
    }
    if (i >= len || (s[i] != 'a' && s[i] != 'b') || (s[i] == 'b' && src->sign < 0))
        return ROZ_EINVAL;
    src->kind = (uint8_t)s[i++];
    if (i >= len || (s[i] == '0' && i + 1 < len))
        return ROZ_EINVAL;
    for (; i < len; i++) {
        if (s[i] < '0' || s[i] > '9')
            return ROZ_EINVAL;
        n = n * 10u + (unsigned)(s[i] - '0');
        if (n >= ROZ_JOY_MAX)
            return ROZ_EINVAL;
    }
    src->index = (uint8_t)n;
    return ROZ_OK;
}

int roz_joy_map_parse(const char *what, const char *text, roz_joy_map_t *map, char *err,
                      size_t errlen)
{
    const char *p = text;
    memset(map, 0, sizeof *map);
    if (what == NULL)
        what = "Joy map";
    if (text == NULL)
        return ROZ_EINVAL;
    while (*p != '\0') {
        if (*p == ' ') {
            p++;
            continue;
        }
        size_t len = strcspn(p, " ");
        const char *eq = memchr(p, '=', len);
        char name[ENTRY_MAX + 8] = "remote.";
        roz_operator_field_t f = ROZ_OPERATOR_NONE;
        roz_joy_source_t src;
        size_t nlen = eq != NULL ? (size_t)(eq - p) : 0;
        const char *why = NULL;

        if (eq == NULL || nlen == 0 || len > ENTRY_MAX) {
            why = "expected FIELD=SOURCE";
        } else {
            memcpy(name + 7, p, nlen);
            if (roz_operator_field_parse(name, 7 + nlen, &f) != ROZ_OK || !is_remote(f))
                why = "not a field of the remote (lx, ly, rx, ry, l2, r2, btn.r1, btn.l1, "
                      "btn.start, btn.select, btn.r2, btn.l2, btn.f1, btn.f2, btn.a, btn.b, "
                      "btn.x, btn.y, btn.up, btn.right, btn.down, btn.left)";
            else if (map->field[f].kind != 0)
                why = "the field is mapped twice";
            else if (parse_source(eq + 1, len - nlen - 1, &src) != ROZ_OK)
                why = "expected aN (axis N), -aN (axis N negated) or bN (button N), N in 0..31";
        }
        if (why != NULL) {
            (void)roz_format(err, errlen, "%s = \"%s\": \"%.*s\": %s", what, text,
                             (int)(len > ENTRY_MAX ? ENTRY_MAX : len), p, why);
            memset(map, 0, sizeof *map);
            return ROZ_EINVAL;
        }
        map->field[f] = src;
        p += len;
    }
    return ROZ_OK;
}

int roz_joy_remote(const roz_joy_map_t *map, const float *axes, uint32_t n_axes,
                   const int32_t *buttons, uint32_t n_buttons, roz_operator_remote_t *out)
{
    float *stick[] = { &out->lx, &out->ly, &out->rx, &out->ry, &out->l2, &out->r2 };
    memset(out, 0, sizeof *out);
    if (n_axes > ROZ_JOY_MAX || n_buttons > ROZ_JOY_MAX)
        return ROZ_ENOSPC;
    for (unsigned f = ROZ_OPERATOR_REMOTE_LX; f <= ROZ_OPERATOR_REMOTE_BTN_LEFT; f++) {
        const roz_joy_source_t *s = &map->field[f];
        float v;
        if (s->kind == 0)
            continue;
        if (s->kind == 'a') {
            if (s->index >= n_axes)
                return ROZ_ERANGE;
            if (!isfinite(axes[s->index]))
                return ROZ_EINVAL;
            v = (float)s->sign * axes[s->index];
        } else {
            if (s->index >= n_buttons)
                return ROZ_ERANGE;
            v = buttons[s->index] != 0 ? 1.0f : 0.0f;
        }
        if (is_button((roz_operator_field_t)f)) {
            if (s->kind == 'a' ? v > 0.5f : v != 0.0f)
                out->buttons |= ROZ_REMOTE_KEY(f);
        } else {
            *stick[f - ROZ_OPERATOR_REMOTE_LX] = v;
        }
    }
    return ROZ_OK;
}
