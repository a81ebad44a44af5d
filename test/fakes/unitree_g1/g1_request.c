/* SPDX-License-Identifier: Apache-2.0 */
#define _POSIX_C_SOURCE 200809L /* strtok_r */

#include "g1_request.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Argument kinds, one character each in a request's signature:
 *   i  motor slot 0..34        b  0..255 (a uint8 field)
 *   u  0..2^32-1 (a uint32)    n  a command count 0..2^32-1
 *   t  timeout 0..G1_REQ_MAX_TIMEOUT_MS ms
 *   k  the remote's held keys: "-" (none) or the names of Unitree's SDK's
 *      key union, joined by '+' ("A+L2"); u[] gets bit i for the name
 *      g1_remote_key_names[i] (the fake sets the SDK's struct by name)
 *   f  a real that fits a float32 (NaN and infinities pass: the robot may
 *      send them, and a port must cope) */
typedef struct verb {
    const char *name;
    g1_req_kind_t kind;
    const char *sig;
    const char *usage;
} verb_t;

static const verb_t verbs[] = {
    { "motor", G1_REQ_MOTOR, "ifff", "motor I Q DQ TAU" },
    { "motorstate", G1_REQ_MOTORSTATE, "iu", "motorstate I CODE" },
    { "imu", G1_REQ_IMU, "ffffffffff", "imu W X Y Z GX GY GZ AX AY AZ" },
    { "remote", G1_REQ_REMOTE, "kfffff", "remote KEYS|- LX RX RY L2 LY" },
    { "mode_machine", G1_REQ_MODE_MACHINE, "b", "mode_machine M" },
    { "mode_pr", G1_REQ_MODE_PR, "b", "mode_pr P" },
    { "send", G1_REQ_SEND, "", "send" },
    { "corrupt", G1_REQ_CORRUPT, "", "corrupt" },
    { "replay", G1_REQ_REPLAY, "", "replay" },
    { "restart", G1_REQ_RESTART, "", "restart" },
    { "silent", G1_REQ_SILENT, "", "silent" },
    { "commands", G1_REQ_COMMANDS, "", "commands" },
    { "wait_commands", G1_REQ_WAIT_COMMANDS, "nt", "wait_commands N TIMEOUT_MS" },
    { "command", G1_REQ_COMMAND, "", "command" },
    { "command_at", G1_REQ_COMMAND_AT, "n", "command_at K" },
    { "flip_next_command", G1_REQ_FLIP_NEXT, "", "flip_next_command" },
    { "matched", G1_REQ_MATCHED, "", "matched" },
    { "motor_state", G1_REQ_MOTOR_STATE, "i", "motor_state I" },
    { "pause", G1_REQ_PAUSE, "t", "pause MS" },
    { "quit", G1_REQ_QUIT, "", "quit" },
};

static const char *const seps = " \t\r";

const char *const g1_remote_key_names[G1_REMOTE_KEYS] = {
    "R1", "L1", "start", "select", "R2", "L2", "F1", "F2",
    "A",  "B",  "X",     "Y",      "up", "right", "down", "left",
};

/* "-" or names of g1_remote_key_names joined by '+', each once: the set. */
static int parse_keys(const char *s, uint64_t *out)
{
    *out = 0;
    if (strcmp(s, "-") == 0)
        return 0;
    for (const char *at = s;;) {
        size_t n = strcspn(at, "+");
        int k = -1;
        for (int i = 0; i < G1_REMOTE_KEYS && k < 0; i++)
            if (strlen(g1_remote_key_names[i]) == n && memcmp(g1_remote_key_names[i], at, n) == 0)
                k = i;
        if (k < 0 || (*out & (1u << k)) != 0)
            return -1;
        *out |= 1u << k;
        if (at[n] == '\0')
            return 0;
        at += n + 1;
    }
}

/* A decimal integer in [0, max]: digits only (strtoull alone would take a
 * sign, spaces and hex). */
static int parse_uint(const char *s, uint64_t max, uint64_t *out)
{
    uint64_t v = 0;
    if (*s == '\0')
        return -1;
    for (; *s != '\0'; s++) {
        if (*s < '0' || *s > '9')
            return -1;
        unsigned d = (unsigned)(*s - '0');
        if (v > (max - d) / 10u)
            return -1;
        v = v * 10u + d;
    }
    *out = v;
    return 0;
}

static int parse_real(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0')
        return -1;
    /* beyond double ("1e400") or float32: converting it would be undefined;
     * "inf" itself passes, and underflow goes to zero */
    if ((errno == ERANGE && isinf(v)) || (isfinite(v) && fabs(v) > FLT_MAX))
        return -1;
    *out = v;
    return 0;
}

static const char *arg_meaning(char kind)
{
    switch (kind) {
    case 'i': return "a motor slot 0..34";
    case 'b': return "an integer 0..255";
    case 'k': return "'-' or the SDK's key names joined by '+' (A+L2)";
    case 'u': return "an integer 0..4294967295";
    case 'n': return "a count 0..4294967295";
    case 't': return "a timeout in ms 0..600000";
    default: return "a number within float range (or nan, inf)";
    }
}

int g1_request_parse(char *line, g1_request_t *req, char *err, size_t errlen)
{
    char *save = NULL;
    char *tok[G1_REQ_MAX_ARGS + 2];
    size_t ntok = 0;
    for (char *t = strtok_r(line, seps, &save); t != NULL; t = strtok_r(NULL, seps, &save)) {
        if (ntok == sizeof tok / sizeof tok[0]) {
            ntok++; /* too many: counted, not kept */
            break;
        }
        tok[ntok++] = t;
    }
    if (ntok == 0) {
        snprintf(err, errlen, "empty request");
        return -1;
    }
    const verb_t *v = NULL;
    for (size_t i = 0; i < sizeof verbs / sizeof verbs[0]; i++)
        if (strcmp(tok[0], verbs[i].name) == 0)
            v = &verbs[i];
    if (v == NULL) {
        snprintf(err, errlen, "unknown request '%.40s'", tok[0]);
        return -1;
    }
    size_t want = strlen(v->sig);
    if (ntok - 1 != want) {
        snprintf(err, errlen, "%s: takes %zu argument%s (%s)", v->name, want,
                 want == 1 ? "" : "s", v->usage);
        return -1;
    }
    memset(req, 0, sizeof *req);
    req->kind = v->kind;
    size_t nu = 0, nf = 0;
    for (size_t a = 0; a < want; a++) {
        const char *s = tok[a + 1];
        char k = v->sig[a];
        int bad;
        if (k == 'f') {
            bad = parse_real(s, &req->f[nf++]);
        } else if (k == 'k') {
            bad = parse_keys(s, &req->u[nu++]);
        } else {
            uint64_t max = k == 'i'   ? 34u
                           : k == 'b' ? 255u
                           : k == 't' ? G1_REQ_MAX_TIMEOUT_MS
                                      : 0xFFFFFFFFu;
            bad = parse_uint(s, max, &req->u[nu++]);
        }
        if (bad) {
            snprintf(err, errlen, "%s: argument %zu '%.40s' is not %s (%s)", v->name, a + 1, s,
                     arg_meaning(k), v->usage);
            return -1;
        }
    }
    return 0;
}
