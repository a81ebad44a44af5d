/* SPDX-License-Identifier: Apache-2.0 */
/* The words of the faults (private to the core): fault_text.c. */
#ifndef ROZ_FAULT_TEXT_H
#define ROZ_FAULT_TEXT_H

#include <stddef.h>
#include <stdint.h>

/* Numbers of a fault record (num[]): the tick in two halves, then two
 * figures whose meaning depends on the fault. */
enum { N_TICK_LO = 0, N_TICK_HI, N_A, N_B };

/* The text of a fault from its numbers; @p text is the controller's or
 * port's message, or NULL or "" for none (readers: formats; never the tick). */
void roz__fault_format(char *buf, size_t len, unsigned bit, const uint64_t num[4],
                       const char *text);

#endif /* ROZ_FAULT_TEXT_H */
