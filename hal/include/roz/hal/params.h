/* SPDX-License-Identifier: Apache-2.0 */
/**
 * @file roz/hal/params.h
 * @brief Parsing port parameters (string key/values) with errors that name
 *        the key and the value.
 *
 * Common keys every port understands: network_interface ("lo"), enable_monitor
 * (true), command_writer_period_us (2000), state_decimation (1), dds_domain
 * (0). Each port lists the keys it knows; roz_params_check_known() refuses
 * any other, so a misspelt key is an error, not a silent default.
 */
#ifndef ROZ_HAL_PARAMS_H
#define ROZ_HAL_PARAMS_H

#include "roz/config.h"

#include <stddef.h>
#include <stdint.h>

#include "roz/port.h"

#ifdef __cplusplus
extern "C" {
#endif

/** @brief Value of @p key, or NULL when absent (the last one wins).
 *  Context: a port's open(); not the tick. */
const char *roz_params_find(const roz_params_t *p, const char *key);

/**
 * @brief Refuse keys outside @p known (NULL-terminated list).
 * @retval ROZ_OK     all known
 * @retval ROZ_ENOENT an unknown key; @p err names it and the port
 * Context: a port's open(); not the tick.
 */
int roz_params_check_known(const roz_params_t *p, const char *const *known, const char *port,
                           char *err, size_t errlen);

/**
 * @brief Integer parameter in [min, max]; @p out = @p def when absent.
 * @retval ROZ_OK     parsed (or default)
 * @retval ROZ_EINVAL not an integer in range; @p err says "key = value: ..."
 * Context: a port's open(); not the tick.
 */
int roz_params_get_u32(const roz_params_t *p, const char *key, uint32_t def, uint32_t min,
                       uint32_t max, uint32_t *out, char *err, size_t errlen);

/** @brief Floating-point parameter in [min, max] (finite).
 *  Context: a port's open(); not the tick. */
int roz_params_get_double(const roz_params_t *p, const char *key, double def, double min,
                          double max, double *out, char *err, size_t errlen);

/** @brief Boolean parameter: true/false, 1/0, yes/no, on/off.
 *  Context: a port's open(); not the tick. */
int roz_params_get_bool(const roz_params_t *p, const char *key, int def, int *out, char *err,
                        size_t errlen);

/** @brief String parameter; @p out = @p def when absent. Never fails.
 *  Context: a port's open(); not the tick. */
const char *roz_params_get_str(const roz_params_t *p, const char *key, const char *def);

/**
 * @brief Split "key=value" in place into @p out (key and value point into
 *        @p arg, whose '=' becomes a NUL).
 * @retval ROZ_EINVAL no '=' or an empty key
 * Context: start-up (command-line parsing).
 */
int roz_params_split(char *arg, roz_param_t *out);

#ifdef __cplusplus
}
#endif

#endif /* ROZ_HAL_PARAMS_H */
