/* SPDX-License-Identifier: Apache-2.0 */
/* PD control of the three-joint CAN leg (examples/can_leg/leg.toml): a slow
 * squat, hip still, thigh and knee together, closed by each actuator's own
 * PD loop. Every tick the controller sends each joint its position target,
 * the target's velocity as the velocity target, the gains, which ramp in
 * over the first second (the manifest's rate caps would ramp them anyway;
 * ramping here keeps the command equal to what was asked), and no
 * feed-forward torque. */
#include "can_leg_channels.h"
#include "roz_controller.h"

#define JOINTS 3
#define CMDS_PER_JOINT 5 /* position, velocity, stiffness, damping, effort */
#define PI 3.14159265358979323846

static const double stand[JOINTS] = { 0.0, 0.6, -1.4 };   /* rad */
static const double squat[JOINTS] = { 0.0, 0.35, -0.7 };  /* rad: amplitude about stand */
static const double kp[JOINTS] = { 40.0, 50.0, 50.0 };    /* N.m/rad */
static const double kd[JOINTS] = { 1.0, 1.5, 1.5 };       /* N.m.s/rad */

ROZ_PROCESS(tick)
{
    double t = (double)tick / (double)ROZ_CAN_LEG_CONTROL_RATE_HZ; /* seconds */
    double ramp = t > 1.0 ? 1.0 : t;
    double w = 2.0 * PI * 0.25; /* a squat every 4 s */
    double s = roz_sin(w * t), c = roz_cos(w * t);

    for (int j = 0; j < JOINTS; j++) {
        int base = ROZ_CAN_LEG_CMD_HIP_POSITION + CMDS_PER_JOINT * j;
        /* the squat goes down and up: (1 - cos) / 2 from 0 to 1 and back */
        double depth = 0.5 * (1.0 - c);
        roz_command_set(base + 0, stand[j] + squat[j] * depth);
        roz_command_set(base + 1, squat[j] * 0.5 * w * s);
        roz_command_set(base + 2, ramp * kp[j]);
        roz_command_set(base + 3, kd[j]);
        roz_command_set(base + 4, 0.0);
    }
}
