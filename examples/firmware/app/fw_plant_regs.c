/* SPDX-License-Identifier: Apache-2.0 */
/* A firmware's own port in its smallest shape (fw_app.h), with no
 * simulator: the filtered commands go to a drive's command registers and
 * the state comes from its state registers, here a block of memory. What
 * stands in for the drive is one line per command: a velocity command moves
 * its paired position state by cmd * dt, a position command sets it. It
 * counts every value outside the manifest that reaches the registers, as the
 * loopback does. The image that links it measures what an image costs
 * without the loopback (docs/firmware.md, "The UR5 image against 96 KB"). */
#include <string.h>

#include "fw_app.h"

/* ---- types ------------------------------------------------------------------ */

typedef struct fw_regs {
    const roz_manifest_t *m;
    double   dt;                             /* seconds per tick */
    double   cmd[ROZ_CFG_MAX_COMMANDS];      /* the drive's command registers */
    double   state[ROZ_CFG_MAX_STATES + 1];  /* its state registers (+1: never empty) */
    uint64_t violations;
} fw_regs_t;

/* Static storage, never the stack. */
static fw_regs_t regs;

/* ---- the port ---------------------------------------------------------------- */

static int regs_open(void *self, const roz_manifest_t *m, const roz_params_t *p, char *err,
                     size_t errlen)
{
    fw_regs_t *r = self;

    (void)p;
    (void)err;
    (void)errlen;
    memset(r, 0, sizeof *r);
    r->m = m;
    r->dt = 1.0 / (double)m->control_rate_hz;
    return ROZ_OK;
}

static int regs_read(void *self, double *state, size_t n)
{
    fw_regs_t *r = self;

    if (n != r->m->n_states)
        return ROZ_EINVAL;
    memcpy(state, r->state, n * sizeof state[0]);
    return 1; /* the drive updates its registers every tick */
}

static int regs_write(void *self, const double *cmd, size_t n)
{
    fw_regs_t *r = self;
    const roz_manifest_t *m = r->m;

    if (n != m->n_commands)
        return ROZ_EINVAL;
    for (uint16_t i = 0; i < m->n_commands; i++) {
        const roz_channel_t *c = &m->commands[i];
        if (!(cmd[i] >= c->min && cmd[i] <= c->max))
            r->violations++;
        r->cmd[i] = cmd[i];
        if (c->position_state == ROZ_CHANNEL_UNPAIRED)
            continue;
        if (c->type == ROZ_IF_VELOCITY)
            r->state[c->position_state] += cmd[i] * r->dt;
        else if (c->type == ROZ_IF_POSITION)
            r->state[c->position_state] = cmd[i];
    }
    return ROZ_OK;
}

static const roz_port_ops_t regs_ops = {
    .name = "fw/registers",
    .open = regs_open,
    .read = regs_read,
    .write = regs_write,
};

/* ---- the plant ---------------------------------------------------------------- */

static roz_port_t regs_port(void)
{
    roz_port_t p = { &regs_ops, &regs, 0 };
    return p;
}

static uint64_t regs_violations(void)
{
    return regs.violations;
}

const fw_plant_t fw_plant = { regs_port, regs_violations };
