# SPDX-License-Identifier: Apache-2.0
# rozrun --port socketcan refuses, exit 2, naming what is wrong: an interface
# that does not exist here, a CAN key given on the command line over the
# robot's (a CAN id twice), a robot for another port.
# cmake -DROZRUN=... -DCTL=<controller dir> -DSRC=<repository> -P
include(${CMAKE_CURRENT_LIST_DIR}/../../checks.cmake)

set(leg --robot ${SRC}/examples/can_leg/leg.toml --controller ${CTL}/leg_pd.wasm --port socketcan)
expect_error("${leg};--param;network_interface=rozcan9"
             "socketcan: network_interface \"rozcan9\": no such interface")
expect_error("${leg};--param;can_id=hip=1, thigh=2, knee=1"
             "socketcan: hardware.params: can_id: joint \"knee\": id 1 is also that of joint \"hip\"")
expect_error("${leg};--param;reply=fancy"
             "socketcan: hardware.params: reply \"fancy\": unknown reply layout")
expect_error("--robot;ur5;--controller;${CTL}/sine.wasm;--port;socketcan"
             "socketcan: hardware: the socketcan port needs the [hardware] table")
