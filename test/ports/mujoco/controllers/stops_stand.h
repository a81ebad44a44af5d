/* SPDX-License-Identifier: Apache-2.0 */
/* The standing G1 the stop cases start from (test_mujoco_stops.c): the
 * example stand's pose, with legs and waist stiff enough to hold the G1 up
 * as an inverted pendulum (ankles kp 150: the example's 40 tips it over
 * after 1.6 s). Gains ramp in over the first second, as the example's do.
 * Each controller file says what it does at STOP_TICK. */
#ifndef STOPS_STAND_H
#define STOPS_STAND_H

#include "stand.h" /* the examples' standing poses */
#include "unitree_g1_channels.h"

#define STOPS_ROBOT(name) ROZ_UNITREE_G1_##name

#define JOINTS 29

static const double pose[JOINTS] = STAND_G1_POSE;
static const double kp[JOINTS] = {
    200, 200, 150, 200, 200, 150, 200, 200, 150, 200, 200, 150, 200, 200, 200,
    40, 40, 40, 40, 20, 20, 20, 40, 40, 40, 40, 20, 20, 20,
};
static const double kd[JOINTS] = {
    5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5, 5,
    1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1,
};

#include "stops_stand_tick.h"

#endif /* STOPS_STAND_H */
