/* SPDX-License-Identifier: Apache-2.0 */
/* fake_can: MIT-mode CAN actuators for the socketcan port's tests, on one
 * end of a socketpair(AF_UNIX, SOCK_SEQPACKET) carrying struct can_frame
 * records, or on a CAN_RAW socket (vcan). Written from the protocol's
 * description, not from the port: its own packing, its own rounding; it
 * never includes the port's or the codec's headers. README.md. */
#ifndef ROZ_TEST_FAKE_CAN_H
#define ROZ_TEST_FAKE_CAN_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>

#define FAKE_CAN_MAX 8
#define FAKE_CAN_LOG 512

enum { FAKE_P, FAKE_V, FAKE_KP, FAKE_KD, FAKE_T, FAKE_FIELDS };
typedef enum { FAKE_BASIC = 0, FAKE_TEMP_ERROR = 1 } fake_layout_t;
/* kinds of frames an actuator received, in its log */
enum { FAKE_ENTER = 'E', FAKE_EXIT = 'X', FAKE_ZERO = 'Z', FAKE_HOLD = 'H', FAKE_COMMAND = 'C' };

typedef struct fake_actuator_cfg {
    uint16_t      can_id;
    uint16_t      reply_id;              /* frame id of its replies: its own, or the host's */
    fake_layout_t layout;
    double        range[FAKE_FIELDS][2]; /* the firmware's min, max per field */
} fake_actuator_cfg_t;

/* What one actuator has seen and does (a copy: fake_can_view()). */
typedef struct fake_actuator {
    fake_actuator_cfg_t cfg;
    int      motor_mode;
    double   q, dq, tau;                   /* the simulated joint, the actuator's frame */
    int      have_cmd;
    uint16_t code[FAKE_FIELDS];            /* the last command applied, as sent */
    double   cmd[FAKE_FIELDS];             /* and decoded */
    /* holds: command frames without stiffness (damping at most);
     * commands: the ones with stiffness */
    uint64_t frames, enters, exits, zeros, holds, commands, outside_motor_mode;
    uint64_t replies;
    uint64_t before_first_reply;           /* frames other than "enter" before its first reply */
    uint64_t gains_before_all;             /* frames with gains before every actuator replied */
    uint64_t dropped;                      /* frames lost on purpose (drop_next) */
    uint64_t pending;                      /* manual: frames not answered yet */
    uint8_t  last_reply[8];
    int      last_reply_len;
    /* behaviour */
    int      mute, frozen, drop_next;
    uint8_t  error;
    double   jump;                          /* added to the reported position */
} fake_actuator_t;

typedef struct fake_can {
    int              fd;
    unsigned         n;
    double           dt;      /* simulated seconds per command received */
    int              manual;  /* 1: replies wait for fake_can_release() */
    fake_actuator_t  act[FAKE_CAN_MAX];
    char             log[FAKE_CAN_LOG][2]; /* the first frames: actuator index, kind */
    unsigned         n_log;
    uint64_t         received; /* frames read, any */
    uint64_t         strays;   /* frames for no actuator of ours */
    pthread_mutex_t  lock;
    pthread_t        thread;
    atomic_int       stop;
    int              running;
} fake_can_t;

/* Start the bus thread on @p fd (it does not close it). 0, or -1. */
int fake_can_start(fake_can_t *bus, int fd, const fake_actuator_cfg_t *acts, unsigned n,
                   double dt, int manual);
void fake_can_stop(fake_can_t *bus);

/* A copy of actuator @p j, and the bus's counts, taken under the lock. */
void fake_can_view(fake_can_t *bus, unsigned j, fake_actuator_t *out);
uint64_t fake_can_received(fake_can_t *bus);

/* Behaviour (any thread). */
void fake_can_mute(fake_can_t *bus, unsigned j, int on);
void fake_can_freeze(fake_can_t *bus, unsigned j, int on);
void fake_can_error(fake_can_t *bus, unsigned j, uint8_t code);
void fake_can_jump(fake_can_t *bus, unsigned j, double rad);
void fake_can_drop_next(fake_can_t *bus, unsigned j);
void fake_can_set(fake_can_t *bus, unsigned j, double q, double dq);

/* Manual mode: each actuator with a frame not yet answered answers once
 * (its present state). Returns how many replies went out. */
unsigned fake_can_release(fake_can_t *bus);
/* Actuator @p j sends its last reply again. */
int fake_can_replay(fake_can_t *bus, unsigned j);
/* Any frame: id (with CAN_EFF_FLAG, CAN_RTR_FLAG or CAN_ERR_FLAG as wanted). */
int fake_can_send_raw(fake_can_t *bus, uint32_t can_id, const uint8_t *data, uint8_t len);

/* A CAN_RAW socket bound to @p ifname (a vcan), for the bus; -1 on error. */
int fake_can_open_raw(const char *ifname);

/* The reply an actuator would send for @p q, @p dq, @p tau (its packing). */
int fake_can_pack_reply(const fake_actuator_cfg_t *c, double q, double dq, double tau,
                        uint8_t error, uint8_t out[8]);

#endif /* ROZ_TEST_FAKE_CAN_H */
