/* SPDX-License-Identifier: Apache-2.0 */
/* Private to the mujoco port: the rules that bind a manifest to a model
 * (its joints, actuators, effort limits and IMU sensors), written once
 * against a view of the model. The port's open sees MuJoCo's compiled
 * model through it; roz_mujoco_check_model() (what rozgen runs) sees the
 * MJCF reader's (mjcf_scan.h). No MuJoCo here. */
#ifndef ROZ_MJ_RULES_H
#define ROZ_MJ_RULES_H

#include <stddef.h>
#include <stdint.h>

#include "roz/hal/params.h"
#include "roz/manifest.h"
#include "roz/port/mujoco.h"

enum { ROZ__MJ_MOBILE_NONE, ROZ__MJ_MOBILE_WHEELS, ROZ__MJ_MOBILE_AUTOPILOT };

/* The joints a manifest binds, and what the model calls them. */
typedef struct roz__mj_joints {
    char        buf[ROZ_MUJOCO_MAX_JOINTS][ROZ_MUJOCO_NAME_MAX];
    char        mj_buf[ROZ_MUJOCO_MAX_JOINTS][ROZ_MUJOCO_NAME_MAX];
    const char *names[ROZ_MUJOCO_MAX_JOINTS]; /* the manifest's */
    const char *mj[ROZ_MUJOCO_MAX_JOINTS];    /* the model's (joint_names) */
    uint16_t    n;
    int         mobile;        /* ROZ__MJ_MOBILE_* */
    int16_t     mob_cmd[4];    /* a mobile base's channels, in the order mujoco.c reads them */
    int16_t     mob_state[4];
} roz__mj_joints_t;

/* The manifest's joints with parameters @p p: a differential drive's two
 * wheels (wheel_left, wheel_right), a quadcopter's none, else [hardware]
 * joints or the joints its channels name (the name before the last '/',
 * base_imu not one), each mapped by joint_names. ROZ_OK; else the
 * refusal (rule "mujoco-joint") in @p err. */
int roz__mj_joints_of(const roz_manifest_t *m, const roz_params_t *p, roz__mj_joints_t *out,
                      char *err, size_t errlen);

/* The model's path: @p model, relative to the folder of @p robot_toml
 * (NULL: the working directory). ROZ_OK, or ROZ_EINVAL when it is longer
 * than @p cap. */
int roz__mj_model_path(const char *robot_toml, const char *model, char *out, size_t cap);

/* "hardware.params.model: missing, ..." for robot @p robot_id. */
void roz__mj_model_missing(const char *robot_id, char *err, size_t errlen);

/* 1 when @p robot_id is one of the robots the port's build has a model
 * for (ports/mujoco/models/<robot_id>.model.toml). */
int roz__mj_is_builtin(const char *robot_id);

/* A model as the rules see it. */
typedef struct roz__mj_joint_view {
    int    id;
    int    hinge_or_slide;
    int    limited;  /* actuatorfrcrange applies */
    double range[2];
} roz__mj_joint_view_t;

typedef struct roz__mj_actuator_view {
    int         id;
    const char *name;           /* NULL: none */
    double      gear, gain;     /* gain: 1 where the reader has none */
    int         force_limited;
    double      force[2];
    int         ctrl_limited;   /* 0 where the reader has none */
    double      ctrl[2];
} roz__mj_actuator_view_t;

enum { ROZ__MJ_SENSOR_OTHER, ROZ__MJ_SENSOR_GYRO, ROZ__MJ_SENSOR_ACCELEROMETER };

typedef struct roz__mj_sensor_view {
    const char *name; /* NULL: none */
    int         kind; /* ROZ__MJ_SENSOR_* */
    int         site; /* -1: not on a site */
} roz__mj_sensor_view_t;

typedef struct roz__mj_model_view {
    const char *path; /* as the messages name the model */
    const void *ctx;
    /* joint @p name: ROZ_OK, or ROZ_ENOENT */
    int (*joint)(const void *ctx, const char *name, roz__mj_joint_view_t *out);
    /* the first actuator driving joint @p j (@p name): ROZ_OK, or ROZ_ENOENT */
    int (*actuator)(const void *ctx, const roz__mj_joint_view_t *j, const char *name,
                    roz__mj_actuator_view_t *out);
    int  n_sensors;
    void (*sensor)(const void *ctx, int i, roz__mj_sensor_view_t *out);
} roz__mj_model_view_t;

/* Manifest joint @p name bound to the model's joint @p mj, whose effort
 * the manifest bounds by channel @p effort (NULL: none): NULL, with the
 * joint, its actuator and the torque range [*lo, *hi] roz applies; else the
 * refusal's rule id ("mujoco-joint", "mujoco-effort") and its text in
 * @p err. */
const char *roz__mj_bind_rule(const roz__mj_model_view_t *v, const char *name, const char *mj,
                              const roz_channel_t *effort, roz__mj_joint_view_t *j,
                              roz__mj_actuator_view_t *a, double *lo, double *hi, char *err,
                              size_t errlen);

/* The IMU's sensors (@p gyro, @p acc: the ones named, NULL: the first of
 * their kind): 0 with their indices; else 1 (the gyro) or 2 (the
 * accelerometer) and the refusal (rule "mujoco-imu") in @p err. */
int roz__mj_imu_rule(const roz__mj_model_view_t *v, const char *gyro, const char *acc,
                     int *gyro_i, int *acc_i, char *err, size_t errlen);

#endif /* ROZ_MJ_RULES_H */
