/* SPDX-License-Identifier: Apache-2.0 */
/* Prints a manifest in the canonical JSON of `rozgen --json`, its one
 * writer. Used by roz_manifest_json (a robot.toml read at run time, for
 * rozgen too) and by rozgen's test that the generated C tables print the
 * same bytes. The format:
 *
 *   {
 *     "robot_id": "ur5",
 *     "robot_class": "manipulator",
 *     "control_rate_hz": 100,
 *     "commands": [
 *       {"name": "a/velocity", "interface_type": "velocity", "unit": "rad/s", "limits": [-3.14, 3.14], "default": 0, "max_rate_of_change": 0.5, "position_state_index": 0, "limit_margin": null, "safe_default": "follow"},
 *       ...
 *     ],
 *     "states": [...],
 *     "fall": {"orientation": "base_imu/orientation", "quaternion": [87, 88, 89, 90], "max_tilt_rad": 1, "for_ms": 20},
 *     "hardware": {"port": "unitree/G1", "joints": ["a", "b"], "params": {"dds_domain": "0"}}
 *   }
 *
 * - ASCII, '\n' line ends, a final newline, two-space indent; every key
 *   always present, in this order; channels one per line in manifest
 *   order, ", " and ": " separators; an empty list is [] on its key's line.
 * - Defaults written out ("generic", 0, -1). "limit_margin" is the margin
 *   the filter keeps inside a position state's limits, the default worked
 *   out (roz_manifest_limit_margin()), null on commands and other states.
 * - "inputs" (as "states", without the filter's keys, with
 *   "stale_after_ms") and "fall" (the fall rule: the quaternion's state
 *   indices x, y, z, w) only when the manifest has them.
 * - "hardware" is null without a [hardware] table; "joints" as given,
 *   "params" sorted by key (byte order).
 * - Numbers (always finite) as the shortest %.{p}g, p = 1..17, that reads
 *   back as the same double, an integral value below 1e16 without exponent:
 *   0, -0, 0.5, 1e-05, 1e+16, 6.283185307179586.
 * - Strings as Python's json.dumps(s, ensure_ascii=True): \" \\ \b \f \n
 *   \r \t, every other character outside U+0020..U+007E as \u and four
 *   lower-case hex digits of its UTF-16 code units; '/' not escaped. */
#include "json.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* json.dumps(s, ensure_ascii=True): \uXXXX (UTF-16, lower-case hex) for
 * everything outside printable ASCII. */
static void put_string(const char *s)
{
    const unsigned char *p = (const unsigned char *)s;
    putchar('"');
    while (*p != 0) {
        unsigned long cp = *p++;
        int more = cp >= 0xF0 ? 3 : cp >= 0xE0 ? 2 : cp >= 0xC0 ? 1 : 0;
        if (more > 0)
            cp &= 0x3Fu >> more;
        for (; more > 0 && *p != 0; more--)
            cp = (cp << 6) | (*p++ & 0x3Fu);
        switch (cp) {
        case '"':  fputs("\\\"", stdout); break;
        case '\\': fputs("\\\\", stdout); break;
        case '\b': fputs("\\b", stdout); break;
        case '\f': fputs("\\f", stdout); break;
        case '\n': fputs("\\n", stdout); break;
        case '\r': fputs("\\r", stdout); break;
        case '\t': fputs("\\t", stdout); break;
        default:
            if (cp >= 0x20 && cp < 0x7F) {
                putchar((int)cp);
            } else if (cp >= 0x10000) {
                cp -= 0x10000;
                printf("\\u%04lx\\u%04lx", 0xD800 + (cp >> 10), 0xDC00 + (cp & 0x3FF));
            } else {
                printf("\\u%04lx", cp);
            }
        }
    }
    putchar('"');
}

/* rozgen.fmt.shortest_g (this program keeps the "C" locale). */
static void put_double(double x)
{
    char buf[40];
    const char *e;
    for (int p = 1; p <= 17; p++) {
        snprintf(buf, sizeof buf, "%.*g", p, x);
        if (strtod(buf, NULL) == x)
            break;
    }
    e = strchr(buf, 'e');
    if (e != NULL && atoi(e + 1) >= 0 && atoi(e + 1) < 16)
        snprintf(buf, sizeof buf, "%.*g", atoi(e + 1) + 1, x);
    fputs(buf, stdout);
}

static void put_channels(const char *key, const roz_channel_t *c, const roz_input_rule_t *r,
                         uint16_t n, int states, int as_written)
{
    printf("  \"%s\": [", key);
    for (uint16_t i = 0; i < n; i++) {
        fputs(i == 0 ? "\n    {\"name\": " : ",\n    {\"name\": ", stdout);
        put_string(c[i].name);
        fputs(", \"interface_type\": ", stdout);
        put_string(roz_interface_name(c[i].type));
        fputs(", \"unit\": ", stdout);
        put_string(c[i].unit);
        fputs(", \"limits\": [", stdout);
        put_double(c[i].min);
        fputs(", ", stdout);
        put_double(c[i].max);
        fputs("], \"default\": ", stdout);
        put_double(c[i].default_value);
        fputs(", \"max_rate_of_change\": ", stdout);
        put_double(c[i].max_rate);
        if (states == 2) { /* an operator input: no filter keys */
            printf(", \"stale_after_ms\": %lu", (unsigned long)r[i].stale_after_ms);
            if (r[i].source != ROZ_OPERATOR_NONE) { /* absent without one: text unchanged */
                fputs(", \"source\": ", stdout);
                put_string(roz_operator_field_name(r[i].source));
                fputs(", \"scale\": ", stdout);
                put_double(r[i].scale);
            }
            fputs("}", stdout);
            continue;
        }
        printf(", \"position_state_index\": %ld, \"limit_margin\": ", (long)c[i].position_state);
        /* the margin the filter keeps, the default worked out; or the
         * field as written (0: the default), which rozgen's tables copy */
        if (as_written)
            put_double(c[i].limit_margin);
        else if (states && c[i].type == ROZ_IF_POSITION)
            put_double(roz_manifest_limit_margin(&c[i]));
        else
            fputs("null", stdout);
        fputs(c[i].safe_default == ROZ_SAFE_HOLD ? ", \"safe_default\": \"hold\"}"
                                                 : ", \"safe_default\": \"follow\"}",
              stdout);
    }
    fputs(n == 0 ? "],\n" : "\n  ],\n", stdout);
}

void manifest_json_print(const roz_manifest_t *m, int as_written)
{
    const roz_hardware_t *h = m->hardware;
    fputs("{\n  \"robot_id\": ", stdout);
    put_string(m->robot_id);
    fputs(",\n  \"robot_class\": ", stdout);
    put_string(m->robot_class);
    printf(",\n  \"control_rate_hz\": %lu,\n", (unsigned long)m->control_rate_hz);
    put_channels("commands", m->commands, NULL, m->n_commands, 0, as_written);
    put_channels("states", m->states, NULL, m->n_states, 1, as_written);
    if (m->n_inputs > 0) /* absent without inputs: older readers' text unchanged */
        put_channels("inputs", m->inputs, m->input_rules, m->n_inputs, 2, as_written);
    if (m->remote_estop != 0u) { /* absent without one: older readers' text unchanged */
        const char *sep = "";
        fputs("  \"remote_estop\": [", stdout);
        for (int f = ROZ_OPERATOR_REMOTE_BTN_R1; f <= ROZ_OPERATOR_REMOTE_BTN_LEFT; f++) {
            if ((m->remote_estop & ROZ_REMOTE_KEY(f)) != 0u) {
                fputs(sep, stdout);
                put_string(roz_operator_field_name((roz_operator_field_t)f));
                sep = ", ";
            }
        }
        fputs("],\n", stdout);
    }
    if (m->fall != NULL) { /* absent without a fall rule, as "inputs" */
        const roz_fall_rule_t *r = m->fall;
        fputs("  \"fall\": {\"orientation\": ", stdout);
        put_string(r->orientation);
        printf(", \"quaternion\": [%ld, %ld, %ld, %ld], \"max_tilt_rad\": ", (long)r->quaternion[0],
               (long)r->quaternion[1], (long)r->quaternion[2], (long)r->quaternion[3]);
        put_double(r->max_tilt);
        printf(", \"for_ms\": %lu},\n", (unsigned long)r->for_ms);
    }
    fputs("  \"hardware\": ", stdout);
    if (h == NULL) {
        fputs("null", stdout);
    } else {
        fputs("{\"port\": ", stdout);
        put_string(h->port);
        fputs(", \"joints\": [", stdout);
        for (uint16_t i = 0; i < h->n_joints; i++) {
            fputs(i == 0 ? "" : ", ", stdout);
            put_string(h->joints[i]);
        }
        fputs("], \"params\": {", stdout);
        for (uint16_t i = 0; i < h->n_params; i++) {
            fputs(i == 0 ? "" : ", ", stdout);
            put_string(h->params[i].key);
            fputs(": ", stdout);
            put_string(h->params[i].value);
        }
        fputs("}}", stdout);
    }
    fputs("\n}\n", stdout);
}
