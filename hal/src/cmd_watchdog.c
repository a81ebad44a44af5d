/* SPDX-License-Identifier: Apache-2.0 */
#include "roz/hal/cmd_watchdog.h"

#include <string.h>

#include "roz/error.h"
#include "roz/format.h"
#include "roz/hal/params.h"

/* ---- private ------------------------------------------------------------- */

static uint32_t us_sat(uint64_t ns)
{
    uint64_t us = ns / 1000u;
    return us > UINT32_MAX ? UINT32_MAX : (uint32_t)us;
}

/* ---- public -------------------------------------------------------------- */

int roz_cmd_watchdog_param(const roz_params_t *p, uint32_t control_rate_hz,
                           uint32_t sender_period_us, uint32_t *out_us, char *err, size_t errlen)
{
    uint64_t tick_us = control_rate_hz != 0 ? (1000000u + control_rate_hz - 1u) / control_rate_hz
                                            : 0;
    uint64_t slowest = tick_us > sender_period_us ? tick_us : sender_period_us;
    uint64_t min = ROZ_CMD_WATCHDOG_MIN_PERIODS * slowest;
    uint64_t def = ROZ_CMD_WATCHDOG_DEFAULT_PERIODS * slowest;
    uint32_t v = 0;

    if (def < ROZ_CMD_WATCHDOG_DEFAULT_US)
        def = ROZ_CMD_WATCHDOG_DEFAULT_US;
    if (min < 1u)
        min = 1u;
    if (def > ROZ_CMD_WATCHDOG_MAX_US)
        def = ROZ_CMD_WATCHDOG_MAX_US;
    if (min > ROZ_CMD_WATCHDOG_MAX_US) {
        roz_format(err, errlen,
                   "parameter %s: the tick (%lu Hz) or the command writer (%lu us) is too slow "
                   "for any timeout up to %lu us",
                   ROZ_CMD_WATCHDOG_KEY, (unsigned long)control_rate_hz,
                   (unsigned long)sender_period_us, (unsigned long)ROZ_CMD_WATCHDOG_MAX_US);
        return ROZ_EINVAL;
    }
    if (roz_params_get_u32(p, ROZ_CMD_WATCHDOG_KEY, (uint32_t)def, (uint32_t)min,
                           ROZ_CMD_WATCHDOG_MAX_US, &v, err, errlen) != ROZ_OK) {
        roz_format(err, errlen,
                   "parameter %s = \"%s\": expected a time in %lu..%lu us (at least %u periods "
                   "of the tick at %lu Hz and of the command writer; default %lu)",
                   ROZ_CMD_WATCHDOG_KEY, roz_params_get_str(p, ROZ_CMD_WATCHDOG_KEY, ""),
                   (unsigned long)min, (unsigned long)ROZ_CMD_WATCHDOG_MAX_US,
                   ROZ_CMD_WATCHDOG_MIN_PERIODS, (unsigned long)control_rate_hz,
                   (unsigned long)def);
        return ROZ_EINVAL;
    }
    *out_us = v;
    return ROZ_OK;
}

void roz_cmd_watchdog_init(roz_cmd_watchdog_t *wd, uint32_t timeout_us)
{
    memset(wd, 0, sizeof *wd);
    wd->timeout_ns = (uint64_t)timeout_us * 1000u;
    wd->next_ns = UINT64_MAX;
    atomic_init(&wd->trips, 0u);
    atomic_init(&wd->resumed, 0u);
    atomic_init(&wd->stood_us, 0u);
}

int roz_cmd_watchdog_write(roz_cmd_watchdog_t *wd, uint64_t now_ns, uint32_t *epoch)
{
    uint32_t trips = atomic_load_explicit(&wd->trips, memory_order_acquire);
    int hold = trips != atomic_load_explicit(&wd->resumed, memory_order_acquire);

    if (trips != wd->tick_reported && trips != wd->tick_gap_trips && wd->tick_wrote) {
        /* the first write after a trip read() has not reported: the silence
         * it ends is the one to report */
        wd->tick_gap_trips = trips;
        wd->tick_gap_ns = now_ns > wd->tick_last_ns ? now_ns - wd->tick_last_ns : 0;
    }
    wd->tick_wrote = 1;
    wd->tick_last_ns = now_ns;
    *epoch = trips;
    return hold;
}

int roz_cmd_watchdog_report(roz_cmd_watchdog_t *wd, uint64_t now_ns, uint32_t *silent_us)
{
    uint32_t trips = atomic_load_explicit(&wd->trips, memory_order_acquire);

    if (trips == wd->tick_reported)
        return 0;
    wd->tick_reported = trips;
    if (wd->tick_gap_trips == trips)
        *silent_us = us_sat(wd->tick_gap_ns); /* it wrote since: the silence that ended */
    else /* the sender trips only on a frame the tick wrote: tick_wrote is set */
        *silent_us = now_ns > wd->tick_last_ns ? us_sat(now_ns - wd->tick_last_ns) : 0u;
    return 1;
}

roz_cmd_verdict_t roz_cmd_watchdog_judge(roz_cmd_watchdog_t *wd, uint32_t epoch, int hold,
                                         uint64_t written_ns, uint64_t now_ns)
{
    if (epoch != wd->epoch) {
        /* written before the last trip was seen: never sent; the tick's
         * next write is a hold of the new epoch */
        wd->next_ns = 0;
        return ROZ_CMD_SAFE;
    }
    if (now_ns > written_ns && now_ns - written_ns > wd->timeout_ns) {
        wd->epoch++;
        wd->next_ns = 0;
        atomic_store_explicit(&wd->stood_us, us_sat(now_ns - written_ns), memory_order_relaxed);
        atomic_store_explicit(&wd->trips, wd->epoch, memory_order_release);
        return ROZ_CMD_SAFE;
    }
    wd->next_ns = written_ns + wd->timeout_ns + 1u;
    if (hold) /* sent: the tick may write its commands again */
        atomic_store_explicit(&wd->resumed, epoch, memory_order_release);
    return ROZ_CMD_SEND;
}

uint64_t roz_cmd_watchdog_next_ns(const roz_cmd_watchdog_t *wd)
{
    return wd->next_ns;
}

uint32_t roz_cmd_watchdog_trips(const roz_cmd_watchdog_t *wd)
{
    return atomic_load_explicit(&wd->trips, memory_order_acquire);
}

uint32_t roz_cmd_watchdog_stood_us(const roz_cmd_watchdog_t *wd)
{
    return atomic_load_explicit(&wd->stood_us, memory_order_relaxed);
}
