/* SPDX-License-Identifier: Apache-2.0 */
/* The standing X2 the X2's stop cases start from (test_mujoco_stops.c,
 * test_mujoco_stops_x2): x2_stand's pose, with legs and waist at the
 * manifest's hold gains (the stiffness defaults a stop brings them to) and
 * the G1 stiff stand's ankle strategy; gains ramp in over the first
 * second. It takes the place of stops_stand.h (the same guard), so each of
 * the G1's stop controllers, included after it by an x2_stops_*.c file, is
 * the same stop on the X2. */
#ifndef STOPS_STAND_H
#define STOPS_STAND_H

#include "stand.h" /* the examples' standing poses */
#include "agibot_x2_channels.h"

#define STOPS_ROBOT(name) ROZ_AGIBOT_X2_##name

#define JOINTS 30

static const double pose[JOINTS] = STAND_X2_POSE;
static const double kp[JOINTS] = {
    200, 200, 150, 200, 200, 150, 200, 200, 150, 200, 200, 150, 150, 200, 200,
    40, 40, 40, 40, 20, 20, 20, 40, 40, 40, 40, 20, 20, 20, 20,
};
static const double kd[JOINTS] = {
    5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5,
    1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,
};

#include "stops_stand_tick.h"

#endif /* STOPS_STAND_H */
