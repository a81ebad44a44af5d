/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/error.h
 * @brief Return codes shared by every roz module.
 *
 * Fallible functions return int: ROZ_OK (0) on success, a negative ROZ_E*
 * code on failure, or a non-negative count or index where documented.
 */
#ifndef ROZ_ERROR_H
#define ROZ_ERROR_H

#include "roz/config.h"

#ifdef __cplusplus
extern "C" {
#endif

#define ROZ_OK        0      /**< success */
#define ROZ_EINVAL    (-1)   /**< invalid argument or malformed input */
#define ROZ_ENOENT    (-2)   /**< no such channel, manifest or key */
#define ROZ_ENOSPC    (-3)   /**< caller-provided storage is full */
#define ROZ_ENOTSUP   (-4)   /**< operation not supported by this port/build */
#define ROZ_ERANGE    (-5)   /**< value outside its documented range */
#define ROZ_EFAULT    (-6)   /**< a latched safety fault blocks the operation */
#define ROZ_ESTATE    (-7)   /**< call not valid in the object's current state */
#define ROZ_EIO       (-8)   /**< I/O or transport failure */
#define ROZ_ETIMEDOUT (-9)   /**< deadline or budget exceeded */
#define ROZ_ELINK     (-10)  /**< a port's peer restarted, or came back after it was lost */
#define ROZ_ECONFIG   (-11)  /**< the caller and roz were built with different ROZ_CFG_* options */
#define ROZ_ENOMEM    (-12)  /**< the engine (wasm3's heap) could not allocate */
#define ROZ_ETRAP     (-13)  /**< the controller trapped */
#define ROZ_EVERIFY   (-14)  /**< a controller failed verification and was not installed */
#define ROZ_EROBOT    (-15)  /**< the robot reports a fault of its own (a motor's fault code) */
#define ROZ_EWATCHDOG (-16)  /**< a port's command watchdog fired: the tick wrote no command
                                  for the port's command_timeout_us (roz/hal/cmd_watchdog.h) */

/* A result that must not be ignored. With C++17 or C23 `[[nodiscard]]`,
 * which a cast to void silences; GCC's older attribute cannot be silenced
 * that way: assign the result. */
#if defined(__cplusplus) && __cplusplus >= 201703L
#define ROZ_NODISCARD [[nodiscard]]
#elif !defined(__cplusplus) && defined(__STDC_VERSION__) && __STDC_VERSION__ >= 202311L
#define ROZ_NODISCARD [[nodiscard]]
#elif defined(__GNUC__) || defined(__clang__)
#define ROZ_NODISCARD __attribute__((warn_unused_result))
#else
#define ROZ_NODISCARD
#endif

/**
 * @brief Short English description of a return code.
 * @param[in] code a ROZ_E* code or ROZ_OK
 * @return a static string; "unknown error" for codes roz does not define.
 * Context: any; RT-safe.
 */
const char *roz_strerror(int code);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_ERROR_H */
