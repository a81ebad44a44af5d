/* SPDX-License-Identifier: Apache-2.0 */
/* rozrun --operator FILE: a scripted operator. The file is CSV: a header
 * "time_s" then input names (the manifest's [[manifest.inputs]]), then one
 * row per change, its time in seconds of the run (tick T is at T / rate)
 * and a value per input; a row's values hold until the next row's time.
 * Blank lines and lines starting with '#' are skipped. The operator sets
 * the current row's values before every tick, as a remote sending at the
 * loop's rate does, through roz_runtime_input_set(): the runtime applies
 * the inputs' rules to them (a value out of range is clamped, a non-finite
 * one refused; docs/rozrun.md). Read whole at start-up; no heap after. */
#ifndef ROZRUN_OPERATOR_H
#define ROZRUN_OPERATOR_H

#include <stddef.h>
#include <stdint.h>

#include "roz/runtime.h"

typedef struct rozrun_operator {
    const char *path;
    uint16_t    n_cols;      /* inputs named by the header */
    uint16_t   *col_input;   /* column -> input index */
    size_t      n_rows;
    double     *time_s;      /* n_rows, non-decreasing */
    double     *value;       /* n_rows x n_cols */
    size_t      row;         /* tick's thread: the row in force, or n_rows before the first */
} rozrun_operator_t;

/* Reads @p path against @p m's inputs. 0, or -1 with a message on stderr
 * naming the file, line and column. */
int rozrun_operator_load(rozrun_operator_t *op, const char *path, const roz_manifest_t *m);

/* Before the tick at @p tick (time tick / rate_hz): sets the values of the
 * row in force, if any. Wait-free; no heap. */
void rozrun_operator_tick(rozrun_operator_t *op, roz_runtime_t *rt, uint64_t tick,
                          uint32_t rate_hz);

void rozrun_operator_free(rozrun_operator_t *op);

#endif /* ROZRUN_OPERATOR_H */
