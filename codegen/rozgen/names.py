# SPDX-License-Identifier: Apache-2.0
"""C identifiers derived from manifest names."""

import re

_NON_ALNUM_RUN = re.compile(r"[^A-Za-z0-9]+")


def constant_suffix(name: str) -> str:
    """Channel name -> the ``<NAME>`` part of its index constant.

    Upper case, every run of characters other than ASCII letters and digits
    turned into one ``_``, leading and trailing ``_`` stripped:
    ``shoulder_pan_joint/velocity`` -> ``SHOULDER_PAN_JOINT_VELOCITY``,
    ``base_imu/orientation.x`` -> ``BASE_IMU_ORIENTATION_X``. Empty when the
    name has no letter or digit (validation refuses such names).
    """
    return _NON_ALNUM_RUN.sub("_", name).strip("_").upper()


def id_prefix(robot_id: str) -> str:
    """``ur5`` -> ``ROZ_UR5``: prefix of every macro of that robot."""
    return "ROZ_" + robot_id.upper()


def command_constant(robot_id: str, name: str) -> str:
    """Index constant of a command channel: ``ROZ_UR5_CMD_<NAME>``."""
    return id_prefix(robot_id) + "_CMD_" + constant_suffix(name)


def input_constant(robot_id: str, name: str) -> str:
    """Index constant of an operator input: ``ROZ_UR5_INPUT_<NAME>``, the
    state index a controller reads it at (after the states)."""
    return id_prefix(robot_id) + "_INPUT_" + constant_suffix(name)


def state_constant(robot_id: str, name: str) -> str:
    """Index constant of a state channel: ``ROZ_UR5_STATE_<NAME>``."""
    return id_prefix(robot_id) + "_STATE_" + constant_suffix(name)
