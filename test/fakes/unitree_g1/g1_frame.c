/* SPDX-License-Identifier: Apache-2.0 */
#include "g1_frame.h"

#include <string.h>

#include "g1_crc.h"

uint32_t g1_lowcmd_crc(const g1_lowcmd_t *c)
{
    return g1_crc_words(c, G1_LOWCMD_CRC_WORDS);
}

uint32_t g1_lowstate_crc(const g1_lowstate_t *s)
{
    return g1_crc_words(s, G1_LOWSTATE_CRC_WORDS);
}

/* ---- member by member: a struct assignment may copy padding -------------- */

static void motorcmd_copy(g1_motorcmd_t *d, const g1_motorcmd_t *s)
{
    d->mode = s->mode;
    d->q = s->q;
    d->dq = s->dq;
    d->tau = s->tau;
    d->kp = s->kp;
    d->kd = s->kd;
    d->reserve = s->reserve;
}

void g1_lowcmd_copy(g1_lowcmd_t *dst, const g1_lowcmd_t *src)
{
    memset(dst, 0, sizeof *dst);
    dst->mode_pr = src->mode_pr;
    dst->mode_machine = src->mode_machine;
    for (size_t i = 0; i < G1_MOTORS; i++)
        motorcmd_copy(&dst->motor_cmd[i], &src->motor_cmd[i]);
    memcpy(dst->reserve, src->reserve, sizeof dst->reserve);
    dst->crc = src->crc;
}

static void imustate_copy(g1_imustate_t *d, const g1_imustate_t *s)
{
    memcpy(d->quaternion, s->quaternion, sizeof d->quaternion);
    memcpy(d->gyroscope, s->gyroscope, sizeof d->gyroscope);
    memcpy(d->accelerometer, s->accelerometer, sizeof d->accelerometer);
    memcpy(d->rpy, s->rpy, sizeof d->rpy);
    d->temperature = s->temperature;
}

static void motorstate_copy(g1_motorstate_t *d, const g1_motorstate_t *s)
{
    d->mode = s->mode;
    d->q = s->q;
    d->dq = s->dq;
    d->ddq = s->ddq;
    d->tau_est = s->tau_est;
    memcpy(d->temperature, s->temperature, sizeof d->temperature);
    d->vol = s->vol;
    memcpy(d->sensor, s->sensor, sizeof d->sensor);
    d->motorstate = s->motorstate;
    memcpy(d->reserve, s->reserve, sizeof d->reserve);
}

void g1_lowstate_copy(g1_lowstate_t *dst, const g1_lowstate_t *src)
{
    memset(dst, 0, sizeof *dst);
    memcpy(dst->version, src->version, sizeof dst->version);
    dst->mode_pr = src->mode_pr;
    dst->mode_machine = src->mode_machine;
    dst->tick = src->tick;
    imustate_copy(&dst->imu_state, &src->imu_state);
    for (size_t i = 0; i < G1_MOTORS; i++)
        motorstate_copy(&dst->motor_state[i], &src->motor_state[i]);
    memcpy(dst->wireless_remote, src->wireless_remote, sizeof dst->wireless_remote);
    memcpy(dst->reserve, src->reserve, sizeof dst->reserve);
    dst->crc = src->crc;
}

void g1_state_frame(g1_lowstate_t *frame, const g1_lowstate_t *model, uint32_t tick)
{
    g1_lowstate_copy(frame, model);
    frame->tick = tick;
    frame->crc = g1_lowstate_crc(frame);
}

int g1_lowcmd_crc_ok(const g1_lowcmd_t *received)
{
    g1_lowcmd_t fresh;
    g1_lowcmd_copy(&fresh, received);
    return g1_lowcmd_crc(&fresh) == received->crc;
}
