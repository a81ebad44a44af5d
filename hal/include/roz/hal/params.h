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
 *
 * The roz_params_get_*() functions read one key with the common message;
 * the roz_params_parse_*() ones are the grammar of a value alone, for ports
 * whose keys hold lists or ranges and say their own words about them.
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

/** @brief robot.toml's [hardware.params] of @p m (none: empty).
 *  Context: any. */
roz_params_t roz_params_hardware(const roz_manifest_t *m);

/**
 * @brief robot.toml's [hardware.params] of @p m, then @p given (may be
 *        NULL), as one list in @p storage: the last of a key wins.
 * @retval ROZ_OK     @p out the list
 * @retval ROZ_EINVAL more than @p cap; @p err "PORT: N parameters; at most CAP"
 * Context: a port's open(); no heap.
 */
int roz_params_merge(const roz_manifest_t *m, const roz_params_t *given, roz_param_t *storage,
                     size_t cap, const char *port, roz_params_t *out, char *err, size_t errlen);

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

/** @brief roz_params_check_known() with the keys of a port's @p n parameter
 *  rows (roz_port_param_info_t), in their order: the known keys are the
 *  rows the port shows. Context: a port's open(); not the tick. */
int roz_params_check_known_rows(const roz_params_t *p, const roz_port_param_info_t *rows,
                                size_t n, const char *port, char *err, size_t errlen);

/** Called once per problem by a port's registered check of its [hardware]
 *  keys (roz_add_port_rules()): a rule id ("ros2-param", "unknown-key")
 *  and the text after the file name (": parameter ..."). */
typedef void (*roz_params_problem_fn)(void *ctx, const char *rule, const char *text);

/** Where roz_params_report() sends a port's error. */
typedef struct roz_params_reporter {
    roz_params_problem_fn report;
    void                 *ctx;
} roz_params_reporter_t;

/**
 * @brief Hand a port's error @p text to @p reporter (a
 *        roz_params_reporter_t) as the text after the file name: ": " and
 *        @p text, with "..." where @p text filled ROZ_CFG_PROBLEM_LEN and
 *        may have been cut. Itself a roz_params_problem_fn, for a port's
 *        rules run in report mode.
 * Context: host tools and start-up; no heap.
 */
void roz_params_report(void *reporter, const char *rule, const char *text);

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

/**
 * @brief A numeric parameter by its row in the port's own table (the rows
 *        its info shows, roz_port_param_info_t): roz_params_get_u32() or
 *        roz_params_get_double() with the row's bounds and default, so the
 *        parser and `rozrun --port NAME --help` cannot disagree.
 * @retval ROZ_OK     parsed (or the row's default)
 * @retval ROZ_EINVAL not a value in the row's range ("key = value: ..."), or
 *                    no row of that kind for @p key (a port's bug: err says so)
 * Context: a port's open(); not the tick.
 */
int roz_params_get_row_u32(const roz_params_t *p, const roz_port_param_info_t *rows, size_t n,
                           const char *key, uint32_t *out, char *err, size_t errlen);

/** @brief roz_params_get_row_u32() for a ROZ_PORT_PARAM_DOUBLE row.
 *  Context: a port's open(); not the tick. */
int roz_params_get_row_double(const roz_params_t *p, const roz_port_param_info_t *rows, size_t n,
                              const char *key, double *out, char *err, size_t errlen);

/** @brief Boolean parameter: true/false, 1/0, yes/no, on/off.
 *  Context: a port's open(); not the tick. */
int roz_params_get_bool(const roz_params_t *p, const char *key, int def, int *out, char *err,
                        size_t errlen);

/** @brief String parameter; @p out = @p def when absent. Never fails.
 *  Context: a port's open(); not the tick. */
const char *roz_params_get_str(const roz_params_t *p, const char *key, const char *def);

/** One step of a port's parameter check that reports every problem: a
 *  problem of @p call is the open's error when there is no reporter (the
 *  caller returns ROZ_EINVAL), else reported as @p rule, and the check
 *  goes on. Uses the caller's `report`, `ctx`, `err` and sets its `bad`. */
#define ROZ_PARAMS_STEP(rule, call)                                                           \
    do {                                                                                      \
        if ((call) != ROZ_OK) {                                                               \
            if (report == NULL)                                                               \
                return ROZ_EINVAL;                                                            \
            report(ctx, rule, err);                                                           \
            bad = 1;                                                                          \
        }                                                                                     \
    } while (0)

/** One word a choice parameter takes, and the value it stands for. */
typedef struct roz_params_word {
    const char *word;
    int         value;
} roz_params_word_t;

/**
 * @brief A parameter that is one of @p n words (@p def when absent): @p out
 *        the value of the word given.
 * @param expected  what the error says after "expected ": the words, what
 *                  each means
 * @retval ROZ_OK; ROZ_EINVAL, @p err `parameter KEY = "V": expected EXPECTED`
 * Context: a port's open(); not the tick.
 */
int roz_params_get_choice(const roz_params_t *p, const char *key, const char *def,
                          const roz_params_word_t *words, size_t n, const char *expected,
                          int *out, char *err, size_t errlen);

/* ---- values: the grammar of one value, without a message ---------------- */

/** A piece of a parameter's text (not NUL-terminated). */
typedef struct roz_params_span {
    const char *s;
    size_t      n;
} roz_params_span_t;

/** Longest number roz_params_parse_number() reads, characters. */
#define ROZ_PARAMS_NUMBER_MAX 63

/** roz_params_parse_u32() flag: also `0x` followed by hex digits. */
#define ROZ_PARAMS_HEX 1u

/** The interface-name rules of roz_params_ifname_valid(). */
typedef enum {
    /** A-Z a-z 0-9 _ . : - (a name any DDS stack and OS accept) */
    ROZ_PARAMS_IFNAME_PORTABLE,
    /** printable ASCII without spaces or '/' (Linux's rule) */
    ROZ_PARAMS_IFNAME_LINUX
} roz_params_ifname_t;

/** @brief The span of NUL-terminated @p z (NULL: empty). Context: any. */
roz_params_span_t roz_params_span(const char *z);

/** @brief @p s without leading and trailing spaces and tabs. Context: any. */
roz_params_span_t roz_params_trim(roz_params_span_t s);

/** @brief Whether @p s is exactly @p z. Context: any. */
int roz_params_span_is(roz_params_span_t s, const char *z);

/**
 * @brief The next entry of a comma-separated list: @p entry is the text up
 *        to the next ',' (trimmed, possibly empty), @p rest what follows it.
 * @retval 1 an entry was taken (the last one has no ',' after it)
 * @retval 0 @p rest was already used up
 * Context: any. Start with rest = roz_params_span(value); an empty value
 * gives one empty entry.
 */
int roz_params_list_next(roz_params_span_t *rest, roz_params_span_t *entry);

/**
 * @brief An unsigned integer in [min, max]: decimal digits (with
 *        ROZ_PARAMS_HEX also `0x`/`0X` and hex digits); no sign, no blanks.
 * @retval ROZ_OK     @p out set
 * @retval ROZ_EINVAL anything else, out of range included; @p out untouched
 * Context: any.
 */
int roz_params_parse_u32(roz_params_span_t s, unsigned flags, uint32_t min, uint32_t max,
                         uint32_t *out);

/**
 * @brief A finite number: [+-]?(digits[.digits]|.digits)([eE][+-]?digits)?,
 *        at most ROZ_PARAMS_NUMBER_MAX characters, '.' whatever the locale.
 * @retval ROZ_OK     @p out set (correctly rounded)
 * @retval ROZ_EINVAL anything else; @p out untouched
 * Context: any.
 */
int roz_params_parse_number(roz_params_span_t s, double *out);

/**
 * @brief "MIN:MAX", two roz_params_parse_number() numbers (blanks around
 *        each allowed). MIN below MAX is the caller's to check.
 * @retval ROZ_OK / ROZ_EINVAL
 * Context: any.
 */
int roz_params_parse_range(roz_params_span_t s, double *min, double *max);

/** @brief true/false, 1/0, yes/no, on/off. @retval ROZ_OK / ROZ_EINVAL.
 *  Context: any. */
int roz_params_parse_bool(roz_params_span_t s, int *out);

/** What a value roz_params_parse_bool() refuses is told (the one text of
 *  that rule; a port may add the words it takes). */
#define ROZ_PARAMS_EXPECTED_BOOL "expected true or false"

/** @brief Whether @p s is an interface name of 1..@p max characters under
 *         @p rule. Context: any. */
int roz_params_ifname_valid(roz_params_span_t s, size_t max, roz_params_ifname_t rule);

/**
 * @brief What a name roz_params_ifname_valid() refuses under @p rule is
 *        told: "expected an interface name" and the rule, into @p buf.
 * @return as roz_format()
 * Context: any.
 */
int roz_params_ifname_expected(char *buf, size_t len, size_t max, roz_params_ifname_t rule);

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
