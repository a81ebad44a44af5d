/* SPDX-License-Identifier: Apache-2.0 */
/* The mujoco port's parameters: one row a key, which its info shows, its
 * known keys are and its parser reads (ranges, defaults), and the rules of
 * those that need no model. One implementation, run by the port's open
 * and by roz_mujoco_check() (what rozgen runs): no MuJoCo here. */
#include "mj_params.h"

#include <string.h>

#include "roz/format.h"

#define PORT "mujoco"

/* A real parameter without a default of the port's own (a built-in robot's
 * descriptor, models/<robot_id>.model.toml, gives it; 0 read: absent). */
#define MJ_DOUBLE_ROW_NO_DEFAULT(key, min, max, unit, def, help)                               \
    { key, ROZ_PORT_PARAM_STR(min) ".." ROZ_PORT_PARAM_STR(max) unit, def, help,              \
      ROZ_PORT_PARAM_DOUBLE, (min), (max), 0.0 }

/* docs/ports/mujoco.md's table, one row a key. */
const roz_port_param_info_t roz__mj_params[] = {
    ROZ_PORT_PARAM_TEXT_ROW("model", "an MJCF file", "the built-in robot's",
                            "relative to the robot.toml"),
    ROZ_PORT_PARAM_TEXT_ROW("keyframe", "a keyframe's name", "the built-in robot's",
                            "the pose to start from"),
    MJ_DOUBLE_ROW_NO_DEFAULT("timestep", 1e-6, 1, " s", "the built-in robot's",
                             "the physics step; a whole number a tick"),
    ROZ_PORT_PARAM_TEXT_ROW("joint_names", "MANIFEST=MJCF,...", "the same names",
                            "manifest joints bound to MJCF joints"),
    ROZ_PORT_PARAM_TEXT_ROW("imu_gyro", "a sensor's name", "the model's first gyro",
                            "the IMU's angular velocity"),
    ROZ_PORT_PARAM_TEXT_ROW("imu_accelerometer", "a sensor's name", "the model's first",
                            "the IMU's acceleration"),
    ROZ_PORT_PARAM_DOUBLE_ROW("servo_kp", 0, 1e7, 400, "",
                              "the velocity servo's stiffness, N m/rad"),
    ROZ_PORT_PARAM_DOUBLE_ROW("servo_kd", 0, 1e6, 20, "",
                              "the velocity servo's damping, N m s/rad"),
    ROZ_PORT_PARAM_TEXT_ROW("unbound", "lock|limp", "lock", "model joints no channel binds"),
    ROZ_PORT_PARAM_TEXT_ROW("lock", "PATTERN,...", "the built-in robot's",
                            "model joints held rigid, bound or not"),
    ROZ_PORT_PARAM_U32_ROW("latency_ticks", 0, ROZ_MUJOCO_MAX_DELAY, 0, "sensor latency"),
    ROZ_PORT_PARAM_U32_ROW("noise_seed", 0, 4294967295, 1, "the noise's seed"),
    ROZ_PORT_PARAM_DOUBLE_ROW("noise_position", 0, 1, 0, "",
                              "Gaussian noise, standard deviation, channel unit"),
    ROZ_PORT_PARAM_DOUBLE_ROW("noise_velocity", 0, 10, 0, "", "Gaussian noise on velocities"),
    ROZ_PORT_PARAM_DOUBLE_ROW("noise_effort", 0, 100, 0, "", "Gaussian noise on efforts"),
    ROZ_PORT_PARAM_DOUBLE_ROW("noise_gyro", 0, 10, 0, "", "Gaussian noise on the gyro"),
    ROZ_PORT_PARAM_DOUBLE_ROW("noise_accelerometer", 0, 100, 0, "",
                              "Gaussian noise on the accelerometer"),
    ROZ_PORT_PARAM_TEXT_ROW("drop", "FROM:TO", "", "state frames lost"),
    ROZ_PORT_PARAM_TEXT_ROW("freeze", "FROM[:TO]", "", "the robot sends nothing"),
    ROZ_PORT_PARAM_TEXT_ROW("delay", "K@FROM:TO", "", "frames K ticks late (1..15)"),
    ROZ_PORT_PARAM_TEXT_ROW("push", "FX,FY,FZ@BODY@FROM:TO", "",
                            "a force, N, world frame, on a body"),
    ROZ_PORT_PARAM_TEXT_ROW("gantry", "FROM[:TO]", "", "the floating base hung where it is"),
    ROZ_PORT_PARAM_TEXT_ROW("restart", "FROM:TO", "", "the robot's board dies and boots at TO"),
    ROZ_PORT_PARAM_TEXT_ROW("wheel_left", "a joint's name", "the built-in diff_drive's",
                            "a differential drive's wheel"),
    ROZ_PORT_PARAM_TEXT_ROW("wheel_right", "a joint's name", "the built-in diff_drive's",
                            "a differential drive's wheel"),
    MJ_DOUBLE_ROW_NO_DEFAULT("wheel_radius", 1e-4, 10, " m", "the built-in diff_drive's",
                             "a differential drive's wheels"),
    MJ_DOUBLE_ROW_NO_DEFAULT("wheel_separation", 1e-3, 100, " m", "the built-in diff_drive's",
                             "a differential drive's track"),
    MJ_DOUBLE_ROW_NO_DEFAULT("max_thrust", 0, 1e6, " N", "the built-in quadcopter's",
                             "a quadcopter's total rotor thrust"),
    /* perturbations: the robot and its world other than the model says */
    ROZ_PORT_PARAM_TEXT_ROW("payload", "KG@BODY[@X,Y,Z];...", "",
                            "mass added to a body, at its centre of mass or X,Y,Z m in its frame"),
    ROZ_PORT_PARAM_DOUBLE_ROW("mass_scale", 0.1, 10, 1, "",
                              "every robot body's mass and inertia, times this"),
    ROZ_PORT_PARAM_DOUBLE_ROW("friction_scale", 0.01, 10, 1, "",
                              "every geom's sliding friction (floor, feet), times this"),
    ROZ_PORT_PARAM_TEXT_ROW("strength_scale", "S[@JOINT];..., S in 0..1", "1",
                            "the effort a joint's motor gives (all, or the model's joint)"),
    ROZ_PORT_PARAM_DOUBLE_ROW("gains_scale", 0, 10, 1, "",
                              "the stiffness and damping the drivers apply, times this"),
    ROZ_PORT_PARAM_DOUBLE_ROW("joint_damping", 0, 1000, 0, "",
                              "damping added to every bound joint, N m s/rad"),
    ROZ_PORT_PARAM_DOUBLE_ROW("joint_armature", 0, 100, 0, "",
                              "armature added to every bound joint, kg m^2"),
    ROZ_PORT_PARAM_U32_ROW("command_latency_ticks", 0, ROZ_MUJOCO_MAX_DELAY, 0,
                           "command latency: ticks from write() to the drivers"),
    ROZ_PORT_PARAM_DOUBLE_ROW("bias_position", 0, 1, 0, "",
                              "encoder offset per joint, drawn once: standard deviation"),
    ROZ_PORT_PARAM_DOUBLE_ROW("bias_gyro", 0, 10, 0, "", "gyro offset per axis, drawn once"),
    ROZ_PORT_PARAM_DOUBLE_ROW("bias_accelerometer", 0, 100, 0, "",
                              "accelerometer offset per axis, drawn once"),
    ROZ_PORT_PARAM_DOUBLE_ROW("bias_orientation", 0, 0.5, 0, "",
                              "the IMU's mounting error per axis, rad, drawn once"),
};
const size_t roz__mj_n_params = sizeof roz__mj_params / sizeof roz__mj_params[0];

const roz_port_info_t roz__mj_info = {
    .summary = "a robot in physics on MuJoCo (the real robot's actuator law, simulated time)",
    .header = "roz/port/mujoco.h",
    ROZ_PORT_INFO_PARAMS(roz__mj_params),
    .no_crc = "physics in the same process: no wire, no CRC",
    .no_sequence = "physics in the same process: no sequence numbers",
    .no_link = "physics in the same process: no link to replay, restart or lose",
};

/* a problem: the open's error (no report), or one report and on */
#define STEP(call) ROZ_PARAMS_STEP("mujoco-param", call)
#define REAL(key, out) STEP(roz_params_get_row_double(p, MJ_PARAMS, key, out, err, errlen))
#define WHOLE(key, out) STEP(roz_params_get_row_u32(p, MJ_PARAMS, key, out, err, errlen))

/* "unbound": lock or limp */
static int check_unbound(const roz_params_t *p, char *err, size_t errlen)
{
    static const roz_params_word_t words[] = { { "lock", 0 }, { "limp", 1 } };
    int limp;
    return roz_params_get_choice(p, "unbound", "lock", words, 2, "lock or limp", &limp, err,
                                 errlen);
}

int roz__mj_params_read(const roz_params_t *p, roz__mj_values_t *v, char *err, size_t errlen,
                        roz_params_problem_fn report, void *ctx)
{
    double timestep; /* the model's own when absent: checked here, read once it loaded */
    int bad = 0;

    if (roz_params_check_known_rows(p, MJ_PARAMS, PORT, err, errlen) != ROZ_OK) {
        if (report != NULL)
            report(ctx, "unknown-key", err);
        return ROZ_EINVAL;
    }
    REAL("wheel_radius", &v->wheel_radius);
    REAL("wheel_separation", &v->wheel_separation);
    REAL("max_thrust", &v->max_thrust);
    REAL("servo_kp", &v->servo_kp);
    REAL("servo_kd", &v->servo_kd);
    REAL("noise_position", &v->noise_q);
    REAL("noise_velocity", &v->noise_dq);
    REAL("noise_effort", &v->noise_tau);
    REAL("noise_gyro", &v->noise_gyro);
    REAL("noise_accelerometer", &v->noise_acc);
    REAL("timestep", &timestep);
    WHOLE("latency_ticks", &v->latency);
    WHOLE("noise_seed", &v->seed);
    STEP(check_unbound(p, err, errlen));
    return bad ? ROZ_EINVAL : ROZ_OK;
}

int roz__mj_perturb_read(const roz_params_t *p, roz__mj_perturb_t *v, char *err, size_t errlen,
                         roz_params_problem_fn report, void *ctx)
{
    int bad = 0;

    REAL("mass_scale", &v->mass);
    REAL("friction_scale", &v->friction);
    REAL("gains_scale", &v->gains);
    REAL("joint_damping", &v->damping);
    REAL("joint_armature", &v->armature);
    WHOLE("command_latency_ticks", &v->cmd_latency);
    REAL("bias_position", &v->bias_q);
    REAL("bias_gyro", &v->bias_gyro);
    REAL("bias_accelerometer", &v->bias_acc);
    REAL("bias_orientation", &v->bias_orientation);
    return bad ? ROZ_EINVAL : ROZ_OK;
}

int roz_mujoco_check(const roz_manifest_t *m, roz_params_problem_fn report, void *ctx)
{
    roz_params_reporter_t to = { report, ctx };
    char err[ROZ_CFG_PROBLEM_LEN];
    roz_params_t p = roz_params_hardware(m);
    roz__mj_values_t v;
    roz__mj_perturb_t pv;

    if (roz_params_check_known_rows(&p, MJ_PARAMS, PORT, err, sizeof err) != ROZ_OK) {
        roz_params_report(&to, "unknown-key", err); /* said alone, as the open says it */
        return ROZ_EINVAL;
    }
    int rc = roz__mj_params_read(&p, &v, err, sizeof err, roz_params_report, &to);
    if (roz__mj_perturb_read(&p, &pv, err, sizeof err, roz_params_report, &to) != ROZ_OK)
        rc = ROZ_EINVAL;
    return rc;
}
