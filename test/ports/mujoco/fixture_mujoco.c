/* SPDX-License-Identifier: Apache-2.0 */
/* The mujoco port's conformance fixture: the simulated robot is the peer,
 * in the same process. Physics has no wire: no CRC, no sequence, no link
 * to lose, so the suite's link cases are skipped; a silent peer is a
 * one-tick freeze of the port's own fault injection, for the read that
 * follows. */
/* white-box: the peer is the port's own simulated robot, read in place (roz/private.h) */
#define ROZ_PRIVATE_ACCESS
#include <string.h>

#include "port_fixture.h"
#include "roz/port/mujoco.h"

static roz_mujoco_t mj;
static roz_port_t the_port;

static int mj_fx_open(const roz_manifest_t *m, const roz_params_t *params, roz_port_t *port,
                      char *err, size_t errlen)
{
    the_port = roz_mujoco_port(&mj, NULL, NULL);
    *port = the_port;
    int rc = roz_port_open(port, m, params, err, errlen);
    return rc != ROZ_OK ? rc : roz_port_activate(port);
}

static void mj_fx_peer(roz_peer_frame_t what)
{
    if (what == ROZ_PEER_SILENT) {
        roz_mujoco_fault_t f;
        memset(&f, 0, sizeof f);
        f.kind = ROZ_INJECT_FREEZE;
        f.from = mj.tick;
        f.to = mj.tick + 1;
        (void)roz_mujoco_inject(&mj, &f);
    }
    /* SEND: the next read() makes the frame; the rest the suite skips */
}

static void mj_fx_peer_sent(double *state)
{
    /* the frame the last read() sampled, which it delivers without latency */
    memcpy(state, mj.hist[(mj.tick - 1) % (ROZ_MUJOCO_MAX_DELAY + 1)],
           mj.m->n_states * sizeof state[0]);
}

static void mj_fx_settle(void)
{
    /* write() hands the command to the drivers before it returns */
}

static const double *mj_fx_peer_command(void)
{
    return roz_mujoco_last_command(&mj);
}

static void mj_fx_link(roz_link_t *out)
{
    memset(out, 0, sizeof *out);
}

static void mj_fx_close(void)
{
    (void)roz_port_deactivate(&the_port);
    roz_port_close(&the_port);
}

const roz_port_fixture_t roz_fixture_mujoco = {
    .name = "mujoco",
    .open = mj_fx_open,
    .peer = mj_fx_peer,
    .peer_sent = mj_fx_peer_sent,
    .settle = mj_fx_settle,
    .peer_command = mj_fx_peer_command,
    .link = mj_fx_link,
    .close = mj_fx_close,
};
