/* SPDX-License-Identifier: Apache-2.0 */
/* A port instance laid out by the application's ROZ_CFG_* options against
 * the library's (roz/port.h says why); here is the comparison. */
#include "roz/port.h"

#include <stddef.h>
#include <string.h>

#include "layout.h"
#include "roz/format.h"

int roz__layout_compare(const void *caller, const void *mine, const roz__layout_field_t *fields,
                        size_t n, const char *why, char *err, size_t errlen)
{
    for (size_t i = 0; i < n; i++) {
        uint32_t theirs, ours;
        memcpy(&theirs, (const char *)caller + fields[i].at, sizeof theirs);
        memcpy(&ours, (const char *)mine + fields[i].at, sizeof ours);
        if (theirs != ours) {
            if (err != NULL && errlen > 0)
                roz_format(err, errlen,
                           "%s is %lu in the application, %lu in libroz_core: build both with the "
                           "same ROZ_CONFIG_FILE (%s)",
                           fields[i].name, (unsigned long)theirs, (unsigned long)ours, why);
            return ROZ_ECONFIG;
        }
    }
    return ROZ_OK;
}

int roz_port_layout_check(const roz_port_layout_t *caller, char *err, size_t errlen)
{
    static const roz_port_layout_t mine = ROZ_PORT_LAYOUT_INIT;
    static const roz__layout_field_t fields[] = {
        { "ROZ_CFG_MAX_COMMANDS", offsetof(roz_port_layout_t, max_commands) },
        { "ROZ_CFG_MAX_STATES", offsetof(roz_port_layout_t, max_states) },
        { "ROZ_CFG_MAX_JOINTS", offsetof(roz_port_layout_t, max_joints) },
        { "ROZ_CFG_MAX_PARAMS", offsetof(roz_port_layout_t, max_params) },
        { "ROZ_CFG_ERROR_LEN", offsetof(roz_port_layout_t, error_len) },
        { "ROZ_CFG_MAX_NAME_LEN", offsetof(roz_port_layout_t, max_name_len) },
        { "ROZ_CFG_NAME_ARENA_BYTES", offsetof(roz_port_layout_t, name_arena_bytes) },
        { "ROZ_CFG_PROBLEM_LEN", offsetof(roz_port_layout_t, problem_len) },
    };

    if (caller == NULL)
        return ROZ_EINVAL;
    return roz__layout_compare(caller, &mine, fields, sizeof fields / sizeof fields[0],
                               "the port's instance would be written past its end", err, errlen);
}

/* The misbuilt port's open(): the instance is not touched (self is NULL). */
static int misbuilt_open(void *self, const roz_manifest_t *m, const roz_params_t *p, char *err,
                         size_t errlen)
{
    (void)self;
    (void)m;
    (void)p;
    if (err != NULL && errlen > 0)
        roz_format(err, errlen,
                   "the port's instance has another size in the application than in the "
                   "library: build both with the same ROZ_CONFIG_FILE and compiler settings");
    return ROZ_ECONFIG;
}

static const roz_port_ops_t misbuilt_ops = {
    .name = "misbuilt",
    .open = misbuilt_open,
};

roz_port_t roz_port_misbuilt(void)
{
    roz_port_t p = { &misbuilt_ops, NULL, 0 };
    return p;
}

roz_port_t roz_port_make(const roz_port_ops_t *ops, void *self, const roz_port_layout_t *caller,
                         size_t bytes, size_t size)
{
    if (roz_port_layout_check(caller, NULL, 0) != ROZ_OK || bytes != size)
        return roz_port_misbuilt();
    roz_port_t p = { ops, self, 0 };
    return p;
}
