/* SPDX-License-Identifier: Apache-2.0 */
#define _POSIX_C_SOURCE 200809L
#include "fake_ros2_client.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#ifndef ROZ_FAKE_ROS2
#error "ROZ_FAKE_ROS2: the path of fake_ros2, set by the build"
#endif

/* The next space-separated word of *p into out. */
static int word(char **p, char *out, size_t len)
{
    char *s = *p;
    while (*s == ' ')
        s++;
    size_t n = strcspn(s, " ");
    if (n == 0 || n >= len)
        return -1;
    memcpy(out, s, n);
    out[n] = '\0';
    *p = s + n;
    return 0;
}

static int describe(roz_fake_ros2_t *f)
{
    char buf[32];
    if (roz_fake_ros2_ask(f, "groups") != 0)
        return -1;
    char *p = f->proc.line + 2;
    if (word(&p, buf, sizeof buf) != 0)
        return -1;
    f->n_groups = (unsigned)strtoul(buf, NULL, 10);
    if (f->n_groups == 0 || f->n_groups > FAKE_ROS2_MAX_GROUPS)
        return -1;
    for (unsigned g = 0; g < f->n_groups; g++) {
        if (word(&p, f->group[g], sizeof f->group[g]) != 0)
            return -1;
    }
    for (unsigned g = 0; g < f->n_groups; g++) {
        if (roz_fake_ros2_ask(f, "joints %s", f->group[g]) != 0)
            return -1;
        p = f->proc.line + 2;
        if (word(&p, buf, sizeof buf) != 0)
            return -1;
        f->n_joints[g] = (unsigned)strtoul(buf, NULL, 10);
        if (f->n_joints[g] > FAKE_ROS2_MAX_JOINTS)
            return -1;
        for (unsigned j = 0; j < f->n_joints[g]; j++) {
            if (word(&p, f->joint[g][j], sizeof f->joint[g][j]) != 0)
                return -1;
        }
    }
    return 0;
}

int roz_fake_ros2_start(roz_fake_ros2_t *f, const char *robot, uint32_t domain,
                        const char *const *extra, char *err, size_t errlen)
{
    char dom[16], what[64];
    const char *args[24];
    size_t n = 0;

    memset(f, 0, sizeof *f);
    snprintf(dom, sizeof dom, "%u", (unsigned)domain);
    snprintf(what, sizeof what, "fake_ros2 --robot %s on domain %u", robot, (unsigned)domain);
    args[n++] = "--robot";
    args[n++] = robot;
    args[n++] = "--domain";
    args[n++] = dom;
    for (size_t i = 0; extra != NULL && extra[i] != NULL && n + 1 < 24; i++)
        args[n++] = extra[i];
    args[n] = NULL;
    if (roz_fake_process_start(&f->proc, ROZ_FAKE_ROS2, args, what, err, errlen) != 0)
        return -1;
    if (describe(f) != 0) {
        snprintf(err, errlen, "%s: cannot read its groups (\"%s\")", what, f->proc.line);
        (void)roz_fake_ros2_stop(f);
        return -1;
    }
    return 0;
}

int roz_fake_ros2_ask(roz_fake_ros2_t *f, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int rc = roz_fake_process_vask(&f->proc, fmt, ap);
    va_end(ap);
    return rc;
}

int roz_fake_ros2_stop(roz_fake_ros2_t *f)
{
    return roz_fake_process_stop(&f->proc);
}

int roz_fake_ros2_commands(roz_fake_ros2_t *f, uint64_t *counts)
{
    if (roz_fake_ros2_ask(f, "commands") != 0)
        return -1;
    char *p = f->proc.line + 2, *end;
    for (unsigned g = 0; g < f->n_groups; g++) {
        counts[g] = strtoull(p, &end, 10);
        if (end == p)
            return -1;
        p = end;
    }
    return 0;
}

int roz_fake_ros2_command(roz_fake_ros2_t *f, unsigned g, roz_fake_ros2_cmd_t *out)
{
    if (g >= f->n_groups)
        return -1;
    int rc = roz_fake_ros2_ask(f, "command %s", f->group[g]);
    if (rc == 1 && strcmp(f->proc.line, "err none") == 0)
        return 0;
    if (rc != 0)
        return -1;
    memset(out, 0, sizeof *out);
    char *p = f->proc.line + 2, *end;
    out->sec = (uint32_t)strtoul(p, &end, 10);
    out->nanosec = (uint32_t)strtoul(end, &end, 10);
    out->seq = (uint32_t)strtoul(end, &end, 10);
    p = end;
    if (word(&p, out->frame_id, sizeof out->frame_id) != 0)
        return -1;
    out->ppt = (unsigned)strtoul(p, &end, 10);
    out->n = (unsigned)strtoul(end, &end, 10);
    out->min_len = (unsigned)strtoul(end, &end, 10);
    p = end;
    if (out->n > FAKE_ROS2_MAX_JOINTS)
        return -1;
    for (unsigned i = 0; i < out->n; i++) {
        if (word(&p, out->name[i], sizeof out->name[i]) != 0)
            return -1;
        double *v[6] = { &out->q[i], &out->dq[i], &out->tau[i],
                         &out->kp[i], &out->kd[i], &out->extra[i] };
        for (int k = 0; k < 6; k++) {
            *v[k] = strtod(p, &end);
            if (end == p)
                return -1;
            p = end;
        }
    }
    return 1;
}

int roz_fake_ros2_group(const roz_fake_ros2_t *f, const char *name)
{
    for (unsigned g = 0; g < f->n_groups; g++) {
        if (strcmp(f->group[g], name) == 0)
            return (int)g;
    }
    return -1;
}
