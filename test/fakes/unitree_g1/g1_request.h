/* SPDX-License-Identifier: Apache-2.0 */
/* One request line of the fake G1's control protocol (README.md), parsed
 * and range-checked; nothing here touches the robot or DDS.
 *
 * Context: the fake's main thread. */
#ifndef FAKE_G1_REQUEST_H
#define FAKE_G1_REQUEST_H

#include <stddef.h>
#include <stdint.h>

typedef enum g1_req_kind {
    G1_REQ_MOTOR,         /* motor I Q DQ TAU */
    G1_REQ_MOTORSTATE,    /* motorstate I CODE */
    G1_REQ_IMU,           /* imu W X Y Z GX GY GZ AX AY AZ */
    G1_REQ_REMOTE,        /* remote KEYS|- LX RX RY L2 LY */
    G1_REQ_MODE_MACHINE,  /* mode_machine M */
    G1_REQ_MODE_PR,       /* mode_pr P */
    G1_REQ_SEND,          /* send */
    G1_REQ_CORRUPT,       /* corrupt */
    G1_REQ_REPLAY,        /* replay */
    G1_REQ_RESTART,       /* restart */
    G1_REQ_SILENT,        /* silent */
    G1_REQ_COMMANDS,      /* commands */
    G1_REQ_WAIT_COMMANDS, /* wait_commands N TIMEOUT_MS */
    G1_REQ_COMMAND,       /* command */
    G1_REQ_COMMAND_AT,    /* command_at K */
    G1_REQ_FLIP_NEXT,     /* flip_next_command */
    G1_REQ_MATCHED,       /* matched */
    G1_REQ_MOTOR_STATE,   /* motor_state I */
    G1_REQ_PAUSE,         /* pause MS */
    G1_REQ_QUIT,          /* quit */
} g1_req_kind_t;

#define G1_REQ_MAX_ARGS 10
/* The longest request line read, without its newline. */
#define G1_REQ_MAX_LINE 1024
/* The longest wait_commands timeout. */
#define G1_REQ_MAX_TIMEOUT_MS 600000u

typedef struct g1_request {
    g1_req_kind_t kind;
    uint64_t u[G1_REQ_MAX_ARGS]; /* integer arguments, in order */
    double f[G1_REQ_MAX_ARGS];   /* real arguments, in order */
} g1_request_t;

/* The names of the remote's 16 keys, as Unitree's SDK's key union names
 * its bit-fields ("remote" request's KEYS). */
#define G1_REMOTE_KEYS 16
extern const char *const g1_remote_key_names[G1_REMOTE_KEYS];

/* Parse @p line (NUL-terminated, no newline; it is modified). 0, or -1
 * with the reason, naming the request, in @p err. */
int g1_request_parse(char *line, g1_request_t *req, char *err, size_t errlen);

#endif /* FAKE_G1_REQUEST_H */
