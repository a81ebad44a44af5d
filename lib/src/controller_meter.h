/* SPDX-License-Identifier: Apache-2.0 */
/* Private: the fuel meter every controller engine shares (controller.c).
 * An engine keeps the current slice's fuel in an int64_t of its own,
 * subtracts each charge from it, and calls roz__controller_refuel() when a
 * charge took it below zero; the meter stops the call when the budget is
 * spent or the deadline passed (the result is the trap text), else hands
 * out the next slice. The slices, the deadline checks and the units used
 * are then the same on every engine (docs/budget.md). */
#ifndef ROZ_CONTROLLER_METER_H
#define ROZ_CONTROLLER_METER_H

#include <stdint.h>

#include "roz/controller.h"

/** The traps the meter returns (compared by address). */
extern const char roz__controller_fuel_trap[];
extern const char roz__controller_deadline_trap[];

/** A charge took *fuel below zero: NULL and the next slice in *fuel, or the
 *  trap. */
const char *roz__controller_refuel(roz_controller_t *c, int64_t *fuel);

/** Charges units (none on an unmetered instance): NULL, or the trap. */
const char *roz__controller_charge(roz_controller_t *c, int64_t *fuel, uint64_t units);

#endif /* ROZ_CONTROLLER_METER_H */
