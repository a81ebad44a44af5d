/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/error.h"

const char *roz_strerror(int code)
{
    switch (code) {
    case ROZ_OK:        return "success";
    case ROZ_EINVAL:    return "invalid argument";
    case ROZ_ENOENT:    return "no such entry";
    case ROZ_ENOSPC:    return "no space left in caller-provided storage";
    case ROZ_ENOTSUP:   return "not supported";
    case ROZ_ERANGE:    return "value out of range";
    case ROZ_EFAULT:    return "safety fault latched";
    case ROZ_ESTATE:    return "invalid in the current state";
    case ROZ_EIO:       return "input/output error";
    case ROZ_ETIMEDOUT: return "deadline or budget exceeded";
    case ROZ_EROBOT:    return "the robot reports a fault";
    case ROZ_EWATCHDOG: return "the tick wrote no command for the port's command timeout";
    case ROZ_ELINK:     return "the robot restarted or came back after it was lost";
    case ROZ_ECONFIG:   return "the application and roz were built with different configurations";
    case ROZ_ENOMEM:    return "the WebAssembly engine could not allocate";
    case ROZ_ETRAP:     return "the controller trapped";
    case ROZ_EVERIFY:   return "the controller failed verification";
    default:            return "unknown error";
    }
}
