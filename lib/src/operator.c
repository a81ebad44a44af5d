/* SPDX-License-Identifier: Apache-2.0 */
/* Operator devices' fields (roz/operator.h). */
#include "roz/operator.h"

#include <string.h>

#include "roz/error.h"

static const char *const field_names[ROZ_OPERATOR_FIELD_COUNT_] = {
    [ROZ_OPERATOR_NONE] = "",
    [ROZ_OPERATOR_REMOTE_LX] = "remote.lx",
    [ROZ_OPERATOR_REMOTE_LY] = "remote.ly",
    [ROZ_OPERATOR_REMOTE_RX] = "remote.rx",
    [ROZ_OPERATOR_REMOTE_RY] = "remote.ry",
    [ROZ_OPERATOR_REMOTE_L2] = "remote.l2",
    [ROZ_OPERATOR_REMOTE_R2] = "remote.r2",
    [ROZ_OPERATOR_REMOTE_BTN_R1] = "remote.btn.r1",
    [ROZ_OPERATOR_REMOTE_BTN_L1] = "remote.btn.l1",
    [ROZ_OPERATOR_REMOTE_BTN_START] = "remote.btn.start",
    [ROZ_OPERATOR_REMOTE_BTN_SELECT] = "remote.btn.select",
    [ROZ_OPERATOR_REMOTE_BTN_R2] = "remote.btn.r2",
    [ROZ_OPERATOR_REMOTE_BTN_L2] = "remote.btn.l2",
    [ROZ_OPERATOR_REMOTE_BTN_F1] = "remote.btn.f1",
    [ROZ_OPERATOR_REMOTE_BTN_F2] = "remote.btn.f2",
    [ROZ_OPERATOR_REMOTE_BTN_A] = "remote.btn.a",
    [ROZ_OPERATOR_REMOTE_BTN_B] = "remote.btn.b",
    [ROZ_OPERATOR_REMOTE_BTN_X] = "remote.btn.x",
    [ROZ_OPERATOR_REMOTE_BTN_Y] = "remote.btn.y",
    [ROZ_OPERATOR_REMOTE_BTN_UP] = "remote.btn.up",
    [ROZ_OPERATOR_REMOTE_BTN_RIGHT] = "remote.btn.right",
    [ROZ_OPERATOR_REMOTE_BTN_DOWN] = "remote.btn.down",
    [ROZ_OPERATOR_REMOTE_BTN_LEFT] = "remote.btn.left",
    [ROZ_OPERATOR_TWIST_LINEAR_X] = "twist.linear.x",
    [ROZ_OPERATOR_TWIST_LINEAR_Y] = "twist.linear.y",
    [ROZ_OPERATOR_TWIST_LINEAR_Z] = "twist.linear.z",
    [ROZ_OPERATOR_TWIST_ANGULAR_X] = "twist.angular.x",
    [ROZ_OPERATOR_TWIST_ANGULAR_Y] = "twist.angular.y",
    [ROZ_OPERATOR_TWIST_ANGULAR_Z] = "twist.angular.z",
};

const char *roz_operator_field_name(roz_operator_field_t f)
{
    return (unsigned)f < (unsigned)ROZ_OPERATOR_FIELD_COUNT_ ? field_names[f] : "?";
}

int roz_operator_field_parse(const char *name, size_t len, roz_operator_field_t *f)
{
    if (name == NULL || f == NULL)
        return ROZ_EINVAL;
    for (int i = 1; i < (int)ROZ_OPERATOR_FIELD_COUNT_; i++) {
        if (strlen(field_names[i]) == len && memcmp(field_names[i], name, len) == 0) {
            *f = (roz_operator_field_t)i;
            return ROZ_OK;
        }
    }
    return ROZ_EINVAL;
}

roz_operator_device_t roz_operator_field_device(roz_operator_field_t f)
{
    if (f >= ROZ_OPERATOR_REMOTE_LX && f <= ROZ_OPERATOR_REMOTE_BTN_LEFT)
        return ROZ_OPERATOR_DEVICE_REMOTE;
    if (f >= ROZ_OPERATOR_TWIST_LINEAR_X && f <= ROZ_OPERATOR_TWIST_ANGULAR_Z)
        return ROZ_OPERATOR_DEVICE_TWIST;
    return ROZ_OPERATOR_DEVICE_NONE;
}

double roz_operator_remote_field(const roz_operator_remote_t *r, roz_operator_field_t f)
{
    switch (f) {
    case ROZ_OPERATOR_REMOTE_LX: return r->lx;
    case ROZ_OPERATOR_REMOTE_LY: return r->ly;
    case ROZ_OPERATOR_REMOTE_RX: return r->rx;
    case ROZ_OPERATOR_REMOTE_RY: return r->ry;
    case ROZ_OPERATOR_REMOTE_L2: return r->l2;
    case ROZ_OPERATOR_REMOTE_R2: return r->r2;
    default: break;
    }
    if (f >= ROZ_OPERATOR_REMOTE_BTN_R1 && f <= ROZ_OPERATOR_REMOTE_BTN_LEFT)
        return (r->buttons & ROZ_REMOTE_KEY(f)) != 0u ? 1.0 : 0.0;
    return 0.0;
}

double roz_operator_twist_field(const roz_operator_twist_t *t, roz_operator_field_t f)
{
    if (f >= ROZ_OPERATOR_TWIST_LINEAR_X && f <= ROZ_OPERATOR_TWIST_LINEAR_Z)
        return t->linear[f - ROZ_OPERATOR_TWIST_LINEAR_X];
    if (f >= ROZ_OPERATOR_TWIST_ANGULAR_X && f <= ROZ_OPERATOR_TWIST_ANGULAR_Z)
        return t->angular[f - ROZ_OPERATOR_TWIST_ANGULAR_X];
    return 0.0;
}
